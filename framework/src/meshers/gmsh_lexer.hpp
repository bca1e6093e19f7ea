// Gmsh MSH import: the tokenizer. Whitespace-separated tokens with their line and column, so
// that every error of the reader names file:line:column. Internal to the framework.
#pragma once

#include "stratum/error.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

namespace stratum::gmsh {

struct Token {
  std::string_view text; ///< empty at the end of the file
  int line = 0;
  int column = 0;
};

// Whitespace-separated tokens ("quoted strings" are one token) with their positions.
class Lexer {
public:
  Lexer(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  [[nodiscard]] const std::string& path() const { return path_; }

  [[noreturn]] void fail(const Token& at, const std::string& message) const {
    throw Error(SourceLocation{path_, at.line, at.column}, message);
  }

  /// The next token; at the end of the file an empty token at the end position.
  Token next() {
    skip_space();
    Token t{{}, line_, static_cast<int>(pos_ - line_start_) + 1};
    const std::size_t begin = pos_;
    if (pos_ < text_.size() && text_[pos_] == '"') {
      const std::size_t close = text_.find('"', pos_ + 1);
      if (close == std::string::npos) fail(t, "unterminated quoted string");
      for (std::size_t i = pos_; i < close; ++i)
        if (text_[i] == '\n') new_line(i);
      pos_ = close + 1;
    } else {
      while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    }
    t.text = std::string_view(text_).substr(begin, pos_ - begin);
    return t;
  }

  /// The next token, which must exist; `what` says what was expected.
  Token need(const std::string& what) {
    Token t = next();
    if (t.text.empty()) fail(t, "unexpected end of file; expected " + what);
    return t;
  }

  void expect(std::string_view word) {
    const Token t = next();
    if (t.text != word)
      fail(t, "expected " + std::string(word) + ", found " +
                  (t.text.empty() ? std::string("end of file") : "'" + std::string(t.text) + "'"));
  }

  long long integer(const std::string& what, Token* where = nullptr) {
    const Token t = need(what);
    if (where) *where = t;
    long long v = 0;
    const auto [end, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), v);
    if (ec != std::errc() || end != t.text.data() + t.text.size())
      fail(t, "expected " + what + " (an integer), found '" + std::string(t.text) + "'");
    return v;
  }

  /// A non-negative integer that fits an int.
  int count(const std::string& what, Token* where = nullptr) {
    Token t;
    const long long v = integer(what, &t);
    if (v < 0 || v > 2147483647) fail(t, what + " = " + std::string(t.text) + " is out of range");
    if (where) *where = t;
    return static_cast<int>(v);
  }

  double real(const std::string& what, Token* where = nullptr) {
    const Token t = need(what);
    if (where) *where = t;
    double v = 0;
    const char* begin = t.text.data() + (t.text.size() > 1 && t.text[0] == '+');
    const auto [end, ec] = std::from_chars(begin, t.text.data() + t.text.size(), v);
    if (ec != std::errc() || end != t.text.data() + t.text.size() || !std::isfinite(v))
      fail(t, "expected " + what + " (a finite number), found '" + std::string(t.text) + "'");
    return v;
  }

  /// Skips to the end of a section that is not needed.
  void skip_section(std::string_view name, const Token& start) {
    const std::string end = "$End" + std::string(name);
    for (Token t = next(); t.text != end; t = next())
      if (t.text.empty()) fail(start, "section $" + std::string(name) + " has no " + end);
  }

private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  }
  void new_line(std::size_t at) {
    ++line_;
    line_start_ = at + 1;
  }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') new_line(pos_);
      ++pos_;
    }
  }

  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  std::size_t line_start_ = 0;
  int line_ = 1;
};

} // namespace stratum::gmsh
