// Analysis: from a scene file to the scene as read (scene/), the model built (model/) and a run
// (run/run.cpp).
#include "files.hpp"
#include "meshers/builtin_generators.hpp"
#include "run/analysis_impl.hpp"
#include "scene/scene.hpp"
#include "scene/toml_check.hpp"
#include "stages/builtin_actions.hpp"

namespace stratum {

void register_builtin_factories(Registry& registry) {
  stage::register_builtin_actions(registry);
  register_builtin_mesh_generators(registry);
}

Analysis::Analysis(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Analysis::~Analysis() = default;

std::unique_ptr<Analysis> Analysis::from_string(const std::string& text, const std::string& path,
                                                RunOptions options) {
  toml::table root = io::parse_with_includes(text, path);
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = std::move(options);
  // The framework's own stage actions and mesh generators are registered like a plugin's.
  SceneModel& sm = impl->sm;
  register_builtin_factories(sm.registry);
  sm.catalog = std::make_unique<PluginCatalog>(scene::plugin_directories(root, path, impl->options));
  scene::Scene sc = scene::read(root, path, *sm.catalog, sm.registry);
  sm.build(sc);
  for (const auto& r : sc.history) impl->recorders.emplace_back(r, sm.model);
  impl->checks = std::move(sc.checks);
  return std::unique_ptr<Analysis>(new Analysis(std::move(impl)));
}

std::unique_ptr<Analysis> Analysis::from_file(const std::string& path, RunOptions options) {
  return from_string(read_text_file(path, SourceLocation{path, 0, 0}, "scene file", file_limits::scene), path,
                     std::move(options));
}

const Model& Analysis::model() const { return impl_->sm.model; }
Model& Analysis::model() { return impl_->sm.model; }
std::vector<std::string> Analysis::opened_libraries() const { return impl_->sm.catalog->opened(); }
std::string Analysis::title() const { return impl_->sm.title; }
std::vector<std::string> Analysis::warnings() const { return impl_->sm.warnings; }
const Units& Analysis::units() const { return impl_->sm.units; }

std::vector<RecordedTable> Analysis::recorded() const {
  std::vector<RecordedTable> tables;
  for (const Recorder& r : impl_->recorders) {
    RecordedTable t{r.name(), r.kind(), {"stage", "step", "lambda"}, {}};
    for (const auto& q : r.quantities())
      if (q != "lambda") t.columns.push_back(q); // a global `lambda` is the row's own column
    for (const RecorderRow& row : r.rows()) {
      std::vector<double> v{static_cast<double>(row.stage), static_cast<double>(row.step), row.lambda};
      for (std::size_t i = 0; i < row.values.size() && i < r.quantities().size(); ++i)
        if (r.quantities()[i] != "lambda") v.push_back(row.values[i]);
      t.rows.push_back(std::move(v));
    }
    tables.push_back(std::move(t));
  }
  return tables;
}

} // namespace stratum
