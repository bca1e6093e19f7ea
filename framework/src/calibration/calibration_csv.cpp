// Calibration: reading the laboratory curves (triaxial and direct-shear CSV files), every
// error located by file, line and column (stratum/calibration.hpp).
#include "stratum/calibration.hpp"

#include "csv_fields.hpp"
#include "files.hpp"

#include "stratum/error.hpp"
#include "stratum/parameters.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace stratum::calibration {

namespace {

// ================================================================ CSV

struct Column {
  std::string name;
  bool required;
};

struct CsvRow {
  int line = 0;
  std::vector<double> value; ///< per declared column; NaN if the column is absent
  std::vector<int> col;      ///< 1-based character column of each field (0 if absent)
};

struct CsvTable {
  std::vector<bool> present; ///< per declared column
  std::vector<CsvRow> rows;
};

using csv::trim;

std::string column_list(const std::vector<Column>& cols, bool required) {
  std::string s;
  for (const auto& c : cols)
    if (c.required == required) s += (s.empty() ? "" : ", ") + c.name;
  return s.empty() ? "none" : s;
}

/// Reads a comma-separated table with a header row of known column names.
CsvTable read_csv(const std::string& path, const std::vector<Column>& cols) {
  std::istringstream in(read_text_file(path, SourceLocation{}, "data file", file_limits::csv));
  const std::string allowed =
      "required " + column_list(cols, true) + "; optional " + column_list(cols, false);
  CsvTable t;
  t.present.assign(cols.size(), false);
  std::vector<int> field_of; // header field -> declared column
  bool have_header = false;
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    if (line == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3); // a UTF-8 byte-order mark
    const std::string text = trim(raw);
    if (text.empty() || text[0] == '#') continue;
    // split, remembering where every field starts
    std::vector<std::string> fields;
    std::vector<int> starts;
    csv::split_fields(raw, fields, starts);
    if (!have_header) {
      have_header = true;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        const auto it =
            std::find_if(cols.begin(), cols.end(), [&](const Column& c) { return c.name == fields[i]; });
        if (it == cols.end() && fields[i].find(';') != std::string::npos)
          throw Error({path, line, starts[i]}, "the header '" + text +
                                                   "' is not comma-separated; allowed: columns separated by "
                                                   "commas, " +
                                                   allowed);
        if (it == cols.end())
          throw Error({path, line, starts[i]},
                      "unknown column '" + fields[i] + "' in the header; allowed: " + allowed +
                          " (stresses in kPa, strains as fractions, displacements in m)");
        const int k = static_cast<int>(it - cols.begin());
        if (t.present[k]) throw Error({path, line, starts[i]}, "column '" + fields[i] + "' appears twice");
        t.present[k] = true;
        field_of.push_back(k);
      }
      for (std::size_t k = 0; k < cols.size(); ++k)
        if (cols[k].required && !t.present[k])
          throw Error({path, line, 1}, "the header has no column '" + cols[k].name + "'; " + allowed);
      continue;
    }
    if (fields.size() != field_of.size())
      throw Error({path, line, 1}, std::to_string(fields.size()) + " fields, the header has " +
                                       std::to_string(field_of.size()) +
                                       " (allowed: one number per header column, comma-separated)");
    CsvRow row;
    row.line = line;
    row.value.assign(cols.size(), std::nan(""));
    row.col.assign(cols.size(), 0);
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string& f = fields[i];
      const int k = field_of[i];
      double v = 0;
      const char* first = f.data() + (f.size() > 1 && f[0] == '+' ? 1 : 0);
      const auto [end, ec] = std::from_chars(first, f.data() + f.size(), v);
      if (f.empty() || ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
        throw Error({path, line, starts[i]},
                    "'" + f + "' in column " + cols[k].name +
                        " is not a finite number (allowed: decimal numbers such as 0.012 or 1.2e-2)");
      row.value[k] = v;
      row.col[k] = starts[i];
    }
    t.rows.push_back(std::move(row));
  }
  if (!have_header) throw Error({path, line, 0}, "empty file: no header row; " + allowed);
  if (t.rows.empty()) throw Error({path, line, 0}, "no data rows after the header");
  return t;
}

} // namespace

// ================================================================ reading

std::vector<TriaxialCurve> read_triaxial_csv(const std::string& path) {
  const std::vector<Column> cols = {
      {"sigma3_kPa", true}, {"eps_axial", true}, {"q_kPa", true}, {"eps_vol", false}, {"eps_radial", false}};
  const CsvTable t = read_csv(path, cols);
  std::vector<TriaxialCurve> out;
  for (const auto& row : t.rows) {
    const double s3 = row.value[0], ea = row.value[1], q = row.value[2];
    auto at = [&](int k) { return SourceLocation{path, row.line, row.col[k]}; };
    if (!(s3 > 0))
      throw Error(at(0), "sigma3_kPa = " + number(s3) + "; allowed: > 0 (compression positive, kPa)");
    if (ea < 0 || ea >= 1)
      throw Error(at(1), "eps_axial = " + number(ea) +
                             "; allowed: 0 <= eps_axial < 1 (a fraction, compression positive: 0.05 = 5 %)");
    if (q < 0)
      throw Error(at(2), "q_kPa = " + number(q) + "; allowed: >= 0 (sigma_1 - sigma_3 in compression)");
    for (int k : {3, 4})
      if (t.present[k] && std::abs(row.value[k]) >= 1)
        throw Error(at(k), cols[k].name + " = " + number(row.value[k]) + "; allowed: |" + cols[k].name +
                               "| < 1 (a fraction, compression positive)");
    if (out.empty() || out.back().sigma3 != s3) {
      out.emplace_back();
      out.back().sigma3 = s3;
      out.back().file = path;
    } else if (!(ea > out.back().eps_a.back())) {
      throw Error(
          at(1), "eps_axial = " + number(ea) + " does not increase (previous point " +
                     number(out.back().eps_a.back()) + " on line " + std::to_string(out.back().lines.back()) +
                     "); allowed: each curve (a block of rows with one sigma3_kPa) in increasing eps_axial");
    }
    TriaxialCurve& c = out.back();
    c.eps_a.push_back(ea);
    c.q.push_back(q);
    if (t.present[3]) c.eps_v.push_back(row.value[3]);
    if (t.present[4]) c.eps_r.push_back(row.value[4]);
    c.lines.push_back(row.line);
  }
  return out;
}

std::vector<ShearCurve> read_direct_shear_csv(const std::string& path) {
  const std::vector<Column> cols = {{"sigma_n_kPa", true}, {"du_m", true}, {"tau_kPa", true}};
  const CsvTable t = read_csv(path, cols);
  std::vector<ShearCurve> out;
  for (const auto& row : t.rows) {
    const double sn = row.value[0], du = row.value[1], tau = row.value[2];
    auto at = [&](int k) { return SourceLocation{path, row.line, row.col[k]}; };
    if (!(sn > 0))
      throw Error(at(0), "sigma_n_kPa = " + number(sn) + "; allowed: > 0 (compression positive, kPa)");
    if (du < 0 || du >= 1)
      throw Error(at(1), "du_m = " + number(du) + "; allowed: 0 <= du_m < 1 (shear displacement in metres)");
    if (tau < 0) throw Error(at(2), "tau_kPa = " + number(tau) + "; allowed: >= 0 (shear in one direction)");
    if (out.empty() || out.back().sigma_n != sn) {
      out.emplace_back();
      out.back().sigma_n = sn;
      out.back().file = path;
    } else if (!(du > out.back().du.back())) {
      throw Error(at(1),
                  "du_m = " + number(du) + " does not increase (previous point " +
                      number(out.back().du.back()) + " on line " + std::to_string(out.back().lines.back()) +
                      "); allowed: each curve (a block of rows with one sigma_n_kPa) in increasing du_m");
    }
    ShearCurve& c = out.back();
    c.du.push_back(du);
    c.tau.push_back(tau);
    c.lines.push_back(row.line);
  }
  return out;
}

} // namespace stratum::calibration
