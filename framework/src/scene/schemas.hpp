// The schemas of the scene's own tables: [analysis], [convergence], [mesh], [[mesh.blocks]],
// [units], [output], [[constraints]], [[domains]], [materials.<name>], [contact_laws.<name>],
// [[interfaces]], [[stages]], [[output.history]], [[checks]], and the framework's keys of the
// tables that name a plugin. A plugin's table is checked against the schema its factory declares.
// The scene reader checks the tables against these, and `stratum describe` (scene/reference.cpp)
// prints them: a key the reader accepts is a key the reference lists.
#pragma once

#include "stratum/params.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace stratum::scene {

/// A key that the reader checks by its own code, not through a Schema: a sub-table, an array of
/// tables, a list of names.
struct OtherKey {
  std::string name, type, meaning;
};

/// The keys of a table that is not one flat Schema: the schema and the other keys.
struct TableKeys {
  Schema schema;
  std::vector<OtherKey> other;
  /// The other keys' names, as check_table's `extra` list (views into `other`).
  [[nodiscard]] std::vector<std::string_view> other_names() const;
};

/// The names of a schema's keys (the keys of a plugin table that belong to the scene).
[[nodiscard]] std::vector<std::string_view> key_names(const Schema& schema);

/// The top level: title, include and the sections' tables.
[[nodiscard]] TableKeys top_keys();
/// [units]: force and length (stress follows); stratum/units.hpp.
[[nodiscard]] Schema units_schema();
[[nodiscard]] Schema analysis_schema();
[[nodiscard]] Schema convergence_schema();
[[nodiscard]] TableKeys mesh_keys();
[[nodiscard]] Schema block_schema();
[[nodiscard]] TableKeys output_keys();
[[nodiscard]] TableKeys plugins_keys();
[[nodiscard]] Schema constraint_schema();
/// [[domains]]: cells, element, material; the element's own parameters follow its schema.
[[nodiscard]] Schema domain_schema();
/// [materials.<name>] and [contact_laws.<name>]: model; the model's parameters follow its schema.
[[nodiscard]] Schema material_schema();
[[nodiscard]] Schema contact_law_schema();
/// [[interfaces]]: name, edges, cells, element, law, csv; the element's parameters follow.
[[nodiscard]] Schema interface_schema();
/// [[stages]], with the defaults a stage inherits from [analysis] and [output].
[[nodiscard]] TableKeys stage_keys(long long max_cutbacks, double error_tolerance, bool vtk, long long every);
/// [[stages.actions]] and [[loads]]: type; the action's keys follow its schema.
[[nodiscard]] Schema action_schema();
[[nodiscard]] Schema loads_schema();
[[nodiscard]] TableKeys recorder_keys();
[[nodiscard]] Schema check_schema();

} // namespace stratum::scene
