// Parameter studies, internal: what the study reader (sweep_study.cpp) and a sample's run
// (sweep.cpp) share.
#pragma once

#include "sweep/sweep.hpp"

#include <toml++/toml.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace stratum::sweep {

/// The base scene (or point file) as parsed, includes merged: each sample's text is this with
/// the sample's values set.
struct Study::Base {
  toml::table root;
};

namespace detail {

/// The settlement components of a pile a study may read (columns 2-8 of
/// curves/settlement_components.csv: mm and kN, or the scene's units; head_settlement is the area
/// mean over the head, the curve's `settlement` the mean of its nodes).
[[nodiscard]] const std::vector<std::string>& pile_component_columns();

/// The columns of a point run's CSV that a study may read (`point` outputs).
[[nodiscard]] const std::vector<std::string>& point_columns();

/// A run's columns by name: the pile curve's ("load", "settlement", the components), the
/// recorders' ("<name>.<column>"), or a point file's.
using Columns = std::map<std::string, std::vector<double>>;

/// What one run of a scene (or point file) gives a study: its columns, counts and outcome.
struct RunColumns {
  Columns cols;
  double steps = std::numeric_limits<double>::quiet_NaN();
  double cutbacks = std::numeric_limits<double>::quiet_NaN();
  double iterations = std::numeric_limits<double>::quiet_NaN();
  std::string status = "failed"; ///< converged, stopped or failed
  std::string reason;            ///< why it stopped or failed ("" when converged)
};

/// Runs a scene (point file) text in this process. Never throws for trouble of the run itself:
/// that is the status and reason. `hint` names where the user sees the text ("the sample's
/// scene (stratum sweep --print-scene 5)"), for errors located in it. With write_output the run
/// writes its files to out_dir.
[[nodiscard]] RunColumns run_columns(const std::string& text, const std::string& base_path, bool point,
                                     bool write_output, const std::string& out_dir, const std::string& hint);

/// The rows of a column: all, or those of a stage (1-based, by the stage column of the column's
/// recorder); empty when the run has no such column.
[[nodiscard]] std::vector<double> column_rows(const Columns& cols, const std::string& column, int stage);
/// The curve y(x) of two columns (empty when their lengths differ: not the same steps).
[[nodiscard]] std::vector<std::array<double, 2>> curve_of(const Columns& cols, const std::string& x,
                                                          const std::string& y, int stage);

/// Sets the values (one per parameter) at the parameters' paths of a parsed base file; a
/// parameter with scale = true multiplies what it finds there.
void apply_values(toml::table& root, const std::vector<Parameter>& params, const std::vector<double>& values);

/// Names of parameters and columns: letters, digits, '_', '-', '.'.
[[nodiscard]] bool good_name(const std::string& s);

/// FNV-1a 64 of the texts (each followed by a separator), in 16 hex digits.
[[nodiscard]] std::string hash_of(const std::vector<std::string>& texts);

/// A parameter's path or paths and scale (which must name numbers of the base file: p.integer
/// says whether all are integers, where the value is set rather than scaled). `key` names the
/// base file ("scene", "point") in messages.
void read_paths(const toml::table& t, const std::string& ctx, const std::string& key, toml::table& base_root,
                const std::string& base_path, Parameter& p);

/// The base file a study or calibration table names: scene = "FILE.toml" (stratum run) or
/// point = "FILE.toml" (stratum point), relative to the study file's folder, read whole.
struct BaseFile {
  bool point = false;
  std::string key;  ///< "scene" or "point"
  std::string path; ///< as resolved
  std::string text;
};
/// Reads the base file table `t` (named `ctx` in messages) names; one located Error when it names
/// both kinds, neither, or a file that cannot be read.
[[nodiscard]] BaseFile read_base_file(const toml::table& t, const std::string& ctx,
                                      const std::string& study_path);

/// Applies a study's [fixed] table (if any) and one element-loop thread count (scenes only) to the
/// parsed base file; errors are located in the study file.
void apply_fixed(const toml::table& study_root, toml::table& base_root, const std::string& base_path,
                 bool point, long long threads, const toml::node& threads_where);

/// What a quantity of a scene study may read: the pile curve's columns, and "<recorder>.<column>"
/// for every recorder of the base scene but an interface's (its rows are points, not steps),
/// with the base scene's stage names.
struct StudyColumns {
  std::vector<std::string> allowed;
  std::vector<std::string> stages;
};
[[nodiscard]] StudyColumns scene_study_columns(const toml::table& base);

/// The 1-based index of a stage of the base scene named by `key` of t (a located error names the
/// stages when it is not one).
[[nodiscard]] int stage_index(const toml::table& t, const std::string& key, const std::string& ctx,
                              const StudyColumns& columns);

} // namespace detail

} // namespace stratum::sweep
