// The command line of a benchmark program: its options in one table, from which both the
// parser and the usage text are made.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

namespace stratum::bench {

class Cli {
public:
  explicit Cli(std::string program) : program_(std::move(program)) {}

  /// --name N: a number > 0 (>= 0 when zero_ok).
  Cli& number(std::string name, std::string help, double& v, bool zero_ok = false) {
    return add(std::move(name), "N", std::move(help), [&v, zero_ok](const char* s) {
      char* end = nullptr;
      v = std::strtod(s, &end);
      return *end == '\0' && (zero_ok ? v >= 0 : v > 0);
    });
  }
  /// --name K: an integer >= 1.
  Cli& count(std::string name, std::string help, int& v) {
    return add(std::move(name), "K", std::move(help), [&v](const char* s) {
      char* end = nullptr;
      const long k = std::strtol(s, &end, 10);
      v = static_cast<int>(k);
      return *end == '\0' && k >= 1 && k <= 1000000;
    });
  }
  /// --name ARG: any text.
  Cli& text(std::string name, std::string arg, std::string help, std::string& v) {
    return add(std::move(name), std::move(arg), std::move(help), [&v](const char* s) {
      v = s;
      return true;
    });
  }
  /// --name alone: sets v to `given`.
  Cli& flag(std::string name, std::string help, bool& v, bool given = true) {
    options_.push_back({std::move(name), "", std::move(help), [&v, given](const char*) {
                          v = given;
                          return true;
                        }});
    return *this;
  }

  /// --docs PATH: the file whose section the program rewrites.
  Cli& docs(std::string& path) {
    return text("--docs", "PATH", "file to update (default <source>/docs/benchmarks.md)", path);
  }
  /// --plugin-dir DIR: where the program loads the plugins from.
  Cli& plugin_dir(std::string& dir) {
    return text("--plugin-dir", "DIR", "plugins to load (default: the build tree's)", dir);
  }

  void usage(std::ostream& os) const {
    std::string line = "usage: " + program_;
    const std::string indent(line.size(), ' ');
    std::size_t width = 0;
    for (const auto& o : options_) width = std::max(width, label(o).size());
    std::string out;
    for (const auto& o : options_) {
      const std::string item = " [" + label(o) + "]";
      if (line.size() + item.size() > 96) {
        out += line + "\n";
        line = indent;
      }
      line += item;
    }
    out += line + "\n";
    out += "  -h, --help" + std::string(width > 10 ? width - 10 + 2 : 2, ' ') + "this text\n";
    for (const auto& o : options_)
      out += "  " + label(o) + std::string(width - label(o).size() + 2, ' ') + o.help + "\n";
    os << out;
  }

  /// -1: parsed, go on; 0: the usage was asked for and printed; 2: a wrong option or value (the
  /// usage goes to stderr after one line that names it).
  [[nodiscard]] int parse(int argc, char** argv) const {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        usage(std::cout);
        return 0;
      }
      const auto o =
          std::find_if(options_.begin(), options_.end(), [&](const Option& x) { return x.name == a; });
      if (o == options_.end()) return fail("unknown option '" + a + "'");
      const char* value = nullptr;
      if (!o->arg.empty()) {
        if (i + 1 >= argc) return fail(a + " needs a value " + o->arg);
        value = argv[++i];
      }
      if (!o->set(value)) return fail(a + ": '" + value + "' is not allowed (" + o->help + ")");
    }
    return -1;
  }

private:
  struct Option {
    std::string name, arg, help;
    std::function<bool(const char*)> set;
  };
  static std::string label(const Option& o) { return o.arg.empty() ? o.name : o.name + " " + o.arg; }
  Cli& add(std::string name, std::string arg, std::string help, std::function<bool(const char*)> set) {
    options_.push_back({std::move(name), std::move(arg), std::move(help), std::move(set)});
    return *this;
  }
  int fail(const std::string& what) const {
    std::cerr << program_ << ": " << what << "\n";
    usage(std::cerr);
    return 2;
  }

  std::string program_;
  std::vector<Option> options_;
};

} // namespace stratum::bench
