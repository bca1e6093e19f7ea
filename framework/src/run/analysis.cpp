// Analysis: from a scene file to a built model (scene/read_scene.cpp) and a run (run/run.cpp).
#include "analysis_impl.hpp"
#include "meshers/builtin_generators.hpp"
#include "scene/scene.hpp"
#include "stages/builtin_actions.hpp"
#include "toml_check.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

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
  register_builtin_factories(impl->registry);
  impl->catalog = std::make_unique<PluginCatalog>(scene::plugin_directories(root, path, impl->options));
  impl->build(scene::read(root, path, *impl->catalog, impl->registry));
  return std::unique_ptr<Analysis>(new Analysis(std::move(impl)));
}

std::unique_ptr<Analysis> Analysis::from_file(const std::string& path, RunOptions options) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path))
    throw Error(SourceLocation{path, 0, 0}, "cannot open scene file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path, std::move(options));
}

const Model& Analysis::model() const { return impl_->model; }
Model& Analysis::model() { return impl_->model; }
std::vector<std::string> Analysis::opened_libraries() const { return impl_->catalog->opened(); }
std::string Analysis::title() const { return impl_->title; }
std::vector<std::string> Analysis::warnings() const { return impl_->warnings; }
const Units& Analysis::units() const { return impl_->units; }

} // namespace stratum
