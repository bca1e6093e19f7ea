// The reference of the scene format, generated from the schemas the scene reader checks the
// tables against (framework/src/scene/schemas.cpp) and from the registered plugins' schemas:
// `stratum describe [SECTION]`, `stratum describe --markdown` (docs/scene-reference.md) and the
// parameter lines of `stratum plugins --describe`.
#pragma once

#include "stratum/params.hpp"
#include "stratum/registry.hpp"
#include "stratum/units.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace stratum {

/// A default as it would be written in TOML: 0.5, true, "text", [1, 2].
[[nodiscard]] std::string default_text(const ParamSpec& p);

/// The keys of a schema, two lines each: name, type, unit, allowed values, default (or
/// "required"), then the meaning (the layout of `stratum plugins --describe`). With `units`
/// other than kN, m: units, defaults and bounds as a scene in those units sees them.
void write_schema(std::ostream& out, const Schema& schema);
void write_schema(std::ostream& out, const Schema& schema, const Units& units);

/// The sections of a scene in order: the name `stratum describe` takes (e.g. "stages.actions"),
/// the header as written in a scene (e.g. "[[stages.actions]]") and what it is, in one line.
struct SceneSectionInfo {
  std::string name, header, summary;
};
[[nodiscard]] std::vector<SceneSectionInfo> scene_sections();

/// One line per section.
void list_scene_sections(std::ostream& out);

/// One section in full: every key with its type, unit, allowed values, default and meaning; for
/// a section whose keys depend on what it names (a solver, a mesh generator, a stage action), the
/// keys of each registered one. `section` may be written with its brackets. Throws Error for an
/// unknown section (with the known ones and "did you mean").
void describe_scene_section(std::ostream& out, const Registry& registry, const std::string& section);

/// The whole reference as Markdown (docs/scene-reference.md).
void write_scene_reference_markdown(std::ostream& out, const Registry& registry);

} // namespace stratum
