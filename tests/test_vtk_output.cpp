#include "output/vtk_output.hpp"

#include <catch2/catch.hpp>

#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace test_vtk_output {

namespace fs = std::filesystem;
using stratum::Mesh;
using stratum::OutputArray;
using stratum::OutputStep;
using stratum::VtkSeriesWriter;

namespace {

/// A uniquely named directory under the system temp directory, removed on exit.
struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    std::uniform_int_distribution<unsigned long long> dist;
    std::ostringstream name;
    name << "stratum_vtk_test_" << std::hex << dist(rd);
    path = fs::temp_directory_path() / name.str();
    fs::create_directories(path);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// Four unit squares in a row along x:
///   cell 0: 8-node quad, cell 1: 8-node quad,
///   cell 2: 6-node transition quad (midside nodes on edges 0-1 and 3-0),
///   cell 3: 4-node quad.
/// Corner (i, j) is node i + 5 j (nodes 0-9), then midside nodes 10-17.
Mesh strip_mesh() {
  Mesh m;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 5; ++i) m.nodes.emplace_back(i, j);
  for (int i = 0; i < 3; ++i) m.nodes.emplace_back(i + 0.5, 0.0); // 10, 11, 12: bottom edges
  for (int i = 0; i < 2; ++i) m.nodes.emplace_back(i + 0.5, 1.0); // 13, 14: top edges
  for (int i = 0; i < 3; ++i) m.nodes.emplace_back(i, 0.5);       // 15, 16, 17: vertical edges
  stratum::Cell c0, c1, c2, c3;
  c0.nodes = {0, 1, 6, 5, 10, 16, 13, 15};
  c1.nodes = {1, 2, 7, 6, 11, 17, 14, 16};
  c2.nodes = {2, 3, 8, 7, 12, -1, -1, 17};
  c3.nodes = {3, 4, 9, 8, -1, -1, -1, -1};
  m.cells = {c0, c1, c2, c3};
  return m;
}

double displacement(int node, int comp, int step) {
  return 1e-3 * (node + 1) * (comp == 1 ? -1.0 : 1.0) * (step + 1);
}
double stress(int cell, int comp, int step) { return -10.0 * cell - comp - 0.125 * step; }

/// A step with "displacement" (3 comps) on the nodes, "stress" (4 comps) and
/// "set_id" on the given cells, and 2 integration points per cell.
OutputStep make_step(const Mesh& mesh, std::vector<int> cells, double time, int k) {
  OutputStep s;
  s.time = time;
  s.mesh = &mesh;
  s.cells = std::move(cells);
  OutputArray u{"displacement", 3, {}};
  for (int n = 0; n < static_cast<int>(mesh.nodes.size()); ++n)
    for (int c = 0; c < 3; ++c) u.values.push_back(c == 2 ? 0.0 : displacement(n, c, k));
  OutputArray sig{"stress", 4, {}}, set{"set_id", 1, {}};
  for (int cell : s.cells) {
    for (int c = 0; c < 4; ++c) sig.values.push_back(stress(cell, c, k));
    set.values.push_back(cell == 3 ? 2.0 : 1.0);
  }
  s.point_fields = {u};
  s.cell_fields = {sig, set};
  const auto n_ip = static_cast<Eigen::Index>(2 * s.cells.size());
  s.ip_coords.resize(n_ip, 2);
  OutputArray eps{"plastic_strain", 1, {}};
  for (Eigen::Index p = 0; p < n_ip; ++p) {
    s.ip_coords(p, 0) = 0.25 + 0.5 * static_cast<double>(p);
    s.ip_coords(p, 1) = 0.5;
    eps.values.push_back(1e-4 * static_cast<double>(p) + k);
  }
  s.ip_fields = {eps};
  return s;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The (timestep, file) attributes of the DataSet entries of a .pvd file, in order.
std::vector<std::pair<std::string, std::string>> pvd_entries(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> out;
  auto attr = [](const std::string& tag, const std::string& key) {
    const std::string k = key + "=\"";
    const auto b = tag.find(k);
    if (b == std::string::npos) return std::string("<missing>");
    const auto e = tag.find('"', b + k.size());
    return tag.substr(b + k.size(), e - b - k.size());
  };
  for (auto pos = text.find("<DataSet"); pos != std::string::npos; pos = text.find("<DataSet", pos + 1)) {
    const std::string tag = text.substr(pos, text.find("/>", pos) - pos);
    out.emplace_back(attr(tag, "timestep"), attr(tag, "file"));
  }
  return out;
}

bool has_temp_files(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.ends_with(".tmp")) return true;
  }
  return false;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& p) {
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(p.string().c_str());
  r->Update();
  return r->GetOutput();
}

std::vector<vtkIdType> cell_points(vtkDataSet& d, vtkIdType cell) {
  vtkNew<vtkIdList> ids;
  d.GetCellPoints(cell, ids);
  std::vector<vtkIdType> out;
  for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) out.push_back(ids->GetId(i));
  return out;
}

} // namespace

TEST_CASE("VtkSeriesWriter writes .vtu, .vtp and .pvd series that read back", "[output]") {
  TempDir tmp;
  const fs::path dir = tmp.path / "out" / "nested"; // created by the writer
  const Mesh mesh = strip_mesh();
  VtkSeriesWriter writer(dir.string(), "run");
  CHECK(writer.steps_written() == 0);
  CHECK(writer.pvd_path() == (dir / "run.pvd").string());

  writer.write(make_step(mesh, {0, 1, 2, 3}, 0.5, 0));
  writer.write(make_step(mesh, {3, 2, 0}, 1.0, 1)); // cell 1 inactive, different order
  CHECK(writer.steps_written() == 2);

  for (const char* f : {"run_0.vtu", "run_1.vtu", "run_ip_0.vtp", "run_ip_1.vtp", "run.pvd", "run_ip.pvd"}) {
    INFO(f);
    CHECK(fs::is_regular_file(dir / f));
  }
  CHECK_FALSE(has_temp_files(dir));

  SECTION("step 0 mesh") {
    auto g = read_vtu(dir / "run_0.vtu");
    REQUIRE(g);
    CHECK(g->GetNumberOfPoints() == 18);
    REQUIRE(g->GetNumberOfCells() == 4);
    CHECK(g->GetCellType(0) == VTK_QUADRATIC_QUAD);
    CHECK(g->GetCellType(1) == VTK_QUADRATIC_QUAD);
    CHECK(g->GetCellType(2) == VTK_POLYGON);
    CHECK(g->GetCellType(3) == VTK_QUAD);
    CHECK(cell_points(*g, 0) == std::vector<vtkIdType>{0, 1, 6, 5, 10, 16, 13, 15});
    CHECK(cell_points(*g, 2) == std::vector<vtkIdType>{2, 12, 3, 8, 7, 17});
    CHECK(cell_points(*g, 3) == std::vector<vtkIdType>{3, 4, 9, 8});

    double p[3];
    g->GetPoint(17, p);
    CHECK(p[0] == 2.0);
    CHECK(p[1] == 0.5);
    CHECK(p[2] == 0.0);

    vtkDataArray* u = g->GetPointData()->GetArray("displacement");
    REQUIRE(u != nullptr);
    CHECK(u->GetNumberOfComponents() == 3);
    CHECK(u->GetNumberOfTuples() == 18);
    CHECK(u->GetComponent(17, 0) == displacement(17, 0, 0));
    CHECK(u->GetComponent(17, 1) == displacement(17, 1, 0));
    CHECK(u->GetComponent(17, 2) == 0.0);

    vtkDataArray* s = g->GetCellData()->GetArray("stress");
    REQUIRE(s != nullptr);
    CHECK(s->GetNumberOfComponents() == 4);
    CHECK(s->GetNumberOfTuples() == 4);
    CHECK(s->GetComponent(2, 3) == stress(2, 3, 0));
    vtkDataArray* id = g->GetCellData()->GetArray("set_id");
    REQUIRE(id != nullptr);
    CHECK(id->GetComponent(3, 0) == 2.0);
  }

  SECTION("step 1 holds only the written cells, in the given order") {
    auto g = read_vtu(dir / "run_1.vtu");
    REQUIRE(g);
    CHECK(g->GetNumberOfPoints() == 18);
    REQUIRE(g->GetNumberOfCells() == 3);
    CHECK(g->GetCellType(0) == VTK_QUAD);
    CHECK(g->GetCellType(1) == VTK_POLYGON);
    CHECK(g->GetCellType(2) == VTK_QUADRATIC_QUAD);
    vtkDataArray* u = g->GetPointData()->GetArray("displacement");
    REQUIRE(u != nullptr);
    CHECK(u->GetComponent(4, 1) == displacement(4, 1, 1));
    vtkDataArray* s = g->GetCellData()->GetArray("stress");
    REQUIRE(s != nullptr);
    CHECK(s->GetComponent(0, 1) == stress(3, 1, 1)); // first written cell is mesh cell 3
    CHECK(s->GetComponent(2, 0) == stress(0, 0, 1));
  }

  SECTION("integration point cloud") {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName((dir / "run_ip_1.vtp").string().c_str());
    r->Update();
    vtkPolyData* pd = r->GetOutput();
    REQUIRE(pd != nullptr);
    CHECK(pd->GetNumberOfPoints() == 6);
    CHECK(pd->GetNumberOfVerts() == 6);
    CHECK(pd->GetNumberOfCells() == 6);
    CHECK(pd->GetCellType(5) == VTK_VERTEX);
    double p[3];
    pd->GetPoint(3, p);
    CHECK(p[0] == 1.75);
    CHECK(p[1] == 0.5);
    CHECK(p[2] == 0.0);
    vtkDataArray* eps = pd->GetPointData()->GetArray("plastic_strain");
    REQUIRE(eps != nullptr);
    CHECK(eps->GetComponent(4, 0) == 1e-4 * 4 + 1);
  }

  SECTION("collections") {
    const auto grids = pvd_entries(read_text(dir / "run.pvd"));
    REQUIRE(grids.size() == 2);
    CHECK(grids[0] == std::pair<std::string, std::string>{"0.5", "run_0.vtu"});
    CHECK(grids[1] == std::pair<std::string, std::string>{"1", "run_1.vtu"});
    const auto clouds = pvd_entries(read_text(dir / "run_ip.pvd"));
    REQUIRE(clouds.size() == 2);
    CHECK(clouds[0] == std::pair<std::string, std::string>{"0.5", "run_ip_0.vtp"});
    CHECK(clouds[1] == std::pair<std::string, std::string>{"1", "run_ip_1.vtp"});
    for (const auto& e : grids) CHECK(fs::is_regular_file(dir / e.second));
    for (const auto& e : clouds) CHECK(fs::is_regular_file(dir / e.second));
    const std::string text = read_text(dir / "run.pvd");
    CHECK(text.find("<VTKFile type=\"Collection\" version=\"0.1\"") != std::string::npos);
    CHECK(text.find("<Collection>") != std::string::npos);
    CHECK(text.find("</VTKFile>") != std::string::npos);
  }
}

TEST_CASE("VtkSeriesWriter skips the point cloud of a step without integration points", "[output]") {
  TempDir tmp;
  const Mesh mesh = strip_mesh();
  VtkSeriesWriter writer(tmp.path.string(), "s");
  OutputStep s0 = make_step(mesh, {0, 1, 2, 3}, 0.0, 0);
  s0.ip_coords.resize(0, 2);
  s0.ip_fields.clear();
  writer.write(s0);
  CHECK(fs::is_regular_file(tmp.path / "s_0.vtu"));
  CHECK_FALSE(fs::exists(tmp.path / "s_ip_0.vtp"));
  CHECK_FALSE(fs::exists(tmp.path / "s_ip.pvd"));

  writer.write(make_step(mesh, {0, 1}, 2.0, 1));
  CHECK(fs::is_regular_file(tmp.path / "s_ip_1.vtp"));
  CHECK(pvd_entries(read_text(tmp.path / "s.pvd")).size() == 2);
  const auto clouds = pvd_entries(read_text(tmp.path / "s_ip.pvd"));
  REQUIRE(clouds.size() == 1);
  CHECK(clouds[0] == std::pair<std::string, std::string>{"2", "s_ip_1.vtp"});
  CHECK_FALSE(has_temp_files(tmp.path));
}

TEST_CASE("VtkSeriesWriter throws Error naming the path it cannot write", "[output]") {
  TempDir tmp;
  const Mesh mesh = strip_mesh();
  const OutputStep step = make_step(mesh, {0, 1, 2, 3}, 0.0, 0);

  SECTION("directory below a regular file") {
    std::ofstream(tmp.path / "blocker") << "x";
    const fs::path dir = tmp.path / "blocker" / "out";
    VtkSeriesWriter writer(dir.string(), "s");
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("cannot write '" + dir.string() + "'"));
    CHECK_THROWS_AS(writer.write(step), stratum::Error);
    CHECK(writer.steps_written() == 0);
  }

  SECTION("final name taken by a directory: rename fails, temporary file removed") {
    fs::create_directories(tmp.path / "s_0.vtu" / "keep");
    VtkSeriesWriter writer(tmp.path.string(), "s");
    CHECK_THROWS_WITH(writer.write(step),
                      Catch::Contains("cannot write '" + (tmp.path / "s_0.vtu").string() + "'"));
    CHECK_FALSE(has_temp_files(tmp.path));
    CHECK(writer.steps_written() == 0);
    CHECK_FALSE(fs::exists(tmp.path / "s.pvd"));
  }

  SECTION("temporary name taken by a directory: the VTK writer fails") {
    fs::create_directories(tmp.path / ".s_0.vtu.tmp");
    VtkSeriesWriter writer(tmp.path.string(), "s");
    CHECK_THROWS_WITH(writer.write(step),
                      Catch::Contains("cannot write '" + (tmp.path / "s_0.vtu").string() + "'"));
    CHECK(fs::is_directory(tmp.path / ".s_0.vtu.tmp")); // not ours: left alone
    CHECK_FALSE(fs::exists(tmp.path / "s_0.vtu"));
    CHECK(writer.steps_written() == 0);
  }
}

TEST_CASE("VtkSeriesWriter throws Error naming a field of the wrong size", "[output]") {
  TempDir tmp;
  const Mesh mesh = strip_mesh();
  VtkSeriesWriter writer(tmp.path.string(), "s");
  OutputStep step = make_step(mesh, {0, 1, 2, 3}, 0.0, 0);

  SECTION("point field") {
    step.point_fields[0].values.pop_back();
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("'displacement'"));
  }
  SECTION("cell field") {
    step.cell_fields[1].components = 2;
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("'set_id'"));
  }
  SECTION("integration point field") {
    step.ip_fields[0].values.push_back(0.0);
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("'plastic_strain'"));
  }
  CHECK_THROWS_AS(writer.write(step), stratum::Error);
  CHECK(writer.steps_written() == 0);
  CHECK(fs::is_empty(tmp.path)); // nothing written before validation
}

TEST_CASE("VtkSeriesWriter rejects cells it cannot write", "[output]") {
  TempDir tmp;
  Mesh mesh = strip_mesh();
  VtkSeriesWriter writer(tmp.path.string(), "s");
  OutputStep step = make_step(mesh, {0, 1, 2, 3}, 0.0, 0);

  SECTION("cell index out of range") {
    step.cells[3] = 4;
    CHECK_THROWS_AS(writer.write(step), stratum::Error);
  }
  SECTION("missing corner") {
    mesh.cells[3].nodes[2] = -1;
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("cell 3"));
  }
  SECTION("node out of range") {
    mesh.cells[1].nodes[5] = 99;
    CHECK_THROWS_WITH(writer.write(step), Catch::Contains("cell 1"));
  }
  CHECK(writer.steps_written() == 0);
}

TEST_CASE("VtkSeriesWriter in the background writes the same files and reports errors at finish()",
          "[output]") {
  TempDir tmp;
  const Mesh mesh = strip_mesh();
  // Three steps (one without integration points), written once in the foreground and once in
  // the background, where each step's data is gone (out of scope) before its files are written.
  auto steps = [&] {
    std::vector<OutputStep> v{make_step(mesh, {0, 1, 2, 3}, 0.0, 0), make_step(mesh, {3, 2, 0}, 1.0, 1),
                              make_step(mesh, {0, 1}, 1.0, 2)}; // same time: written at 1 + 1e-6
    v[1].ip_coords.resize(0, 2);
    v[1].ip_fields.clear();
    return v;
  };
  const fs::path fg = tmp.path / "fg", bg = tmp.path / "bg";
  {
    VtkSeriesWriter w(fg.string(), "s");
    for (const auto& st : steps()) w.write(st);
  }
  {
    VtkSeriesWriter w(bg.string(), "s", true);
    for (int k = 0; k < 3; ++k) {
      Mesh copy = mesh;
      OutputStep st = steps()[static_cast<std::size_t>(k)];
      st.mesh = &copy;
      w.write(st);
      copy.nodes.clear(); // the caller's mesh may change once write() has returned
    }
    CHECK(w.steps_written() == 3);
    w.finish();
  }
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fg)) names.push_back(e.path().filename().string());
  CHECK(names.size() == 7); // 3 .vtu, 2 .vtp, 2 .pvd
  for (const auto& n : names) {
    INFO(n);
    CHECK(read_text(fg / n) == read_text(bg / n));
  }
  CHECK_FALSE(fs::exists(bg / "s_ip_1.vtp"));
  CHECK_FALSE(has_temp_files(bg));

  SECTION("a failed background write is thrown by the next write() or by finish()") {
    const fs::path dir = tmp.path / "err";
    fs::create_directories(dir / "s_1.vtu" / "keep"); // step 1 cannot be renamed into place
    VtkSeriesWriter w(dir.string(), "s", true);
    const OutputStep st = make_step(mesh, {0, 1, 2, 3}, 0.0, 0);
    w.write(st);
    OutputStep st1 = st;
    st1.time = 1.0;
    w.write(st1); // returns: the failure happens on the writer's thread
    CHECK_THROWS_WITH(w.finish(), Catch::Contains("cannot write '" + (dir / "s_1.vtu").string() + "'"));
    CHECK(fs::is_regular_file(dir / "s_0.vtu"));
    CHECK_FALSE(has_temp_files(dir));
    w.finish(); // nothing pending any more
  }
}

} // namespace test_vtk_output
