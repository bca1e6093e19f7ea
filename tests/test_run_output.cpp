// The default scene, run as `tools/run` runs it, writes a .pvd collection whose
// files VTK's XML readers read back with the right numbers.
#include <catch2/catch.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace test_run_output {

namespace fs = std::filesystem;

TEST_CASE("cli: the default scene writes a .pvd series that VTK reads back", "[cli][output]") {
  const fs::path out = fs::temp_directory_path() / ("stratum_default_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string scene = std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/lame_axisymmetric.toml";
  const std::string cmd = std::string("STRATUM_PLUGIN_PATH= ") + STRATUM_EXE + " run " + scene + " --out " +
                          out.string() + " > " + (out.string() + ".log") + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const fs::path pvd = out / "lame_axisymmetric.pvd";
  REQUIRE(fs::exists(pvd));

  std::ifstream in(pvd);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::regex ds(R"re(<DataSet timestep="([^"]+)"[^>]*file="([^"]+)")re");
  std::vector<std::pair<double, std::string>> sets;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), ds); it != std::sregex_iterator(); ++it)
    sets.emplace_back(std::stod((*it)[1]), (*it)[2]);
  REQUIRE(sets.size() == 2); // the initial state and the one load step
  CHECK(sets[0].first == 0.0);
  CHECK(sets[1].first == 1.0);

  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName((out / sets[1].second).string().c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  REQUIRE(grid != nullptr);
  CHECK(grid->GetNumberOfCells() == 16);
  vtkDataArray* u = grid->GetPointData()->GetArray("displacement [m]");
  REQUIRE(u != nullptr);
  REQUIRE(u->GetNumberOfComponents() == 3);
  // The largest radial displacement sits on the inner face: u(a) of the Lamé solution.
  double umax = 0;
  for (vtkIdType i = 0; i < u->GetNumberOfTuples(); ++i) umax = std::max(umax, u->GetComponent(i, 0));
  const double exact = (1 + 0.3) * 1.0 / (1000.0 * 3.0) * ((1 - 0.6) * 1.0 + 4.0);
  CHECK(std::abs(umax - exact) / exact < 1e-3);
  vtkDataArray* stress = grid->GetCellData()->GetArray("stress [kPa]");
  REQUIRE(stress != nullptr);
  CHECK(stress->GetNumberOfComponents() == 6);
  CHECK(grid->GetCellData()->GetArray("set_id") != nullptr);

  auto pr = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  pr->SetFileName((out / "lame_axisymmetric_ip_1.vtp").string().c_str());
  pr->Update();
  CHECK(pr->GetOutput()->GetNumberOfPoints() == 16 * 9);
  CHECK(pr->GetOutput()->GetPointData()->GetArray("stress [kPa]") != nullptr);
  fs::remove_all(out);
}

TEST_CASE("cli: the VTK series carries field data per step, strictly increasing times and named components",
          "[cli][output]") {
  // Found on 997ba04: no stage name, load factor or head load in the series; two files shared
  // timestep="1" (ParaView hides one); interface tractions showed as X/Y.
  const fs::path out = fs::temp_directory_path() / ("stratum_fielddata_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string scene = std::string(STRATUM_SOURCE_DIR) + "/inputs/loess_pile/hypoelastic.toml";
  const std::string cmd = std::string("STRATUM_PLUGIN_PATH= ") + STRATUM_EXE + " run " + scene + " --out " +
                          out.string() + " > " + (out.string() + ".log") + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(out / "hypoelastic.pvd");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::regex ds(R"re(<DataSet timestep="([^"]+)"[^>]*file="([^"]+)")re");
  std::vector<std::pair<double, std::string>> sets;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), ds); it != std::sregex_iterator(); ++it)
    sets.emplace_back(std::stod((*it)[1]), (*it)[2]);
  REQUIRE(sets.size() > 10);
  for (std::size_t i = 1; i < sets.size(); ++i) CHECK(sets[i].first > sets[i - 1].first);
  // The last converged head load and settlement of curves/load_settlement.csv.
  double load = 0, settlement = 0;
  {
    std::ifstream c(out / "curves" / "load_settlement.csv");
    std::string line, last;
    while (std::getline(c, line)) last = line;
    load = std::stod(last.substr(0, last.find(',')));
    settlement = std::stod(last.substr(last.find(',') + 1));
  }
  auto read = [&](const std::string& file) {
    auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    r->SetFileName((out / file).string().c_str());
    r->Update();
    return vtkSmartPointer<vtkUnstructuredGrid>(r->GetOutput());
  };
  const auto last = read(sets.back().second);
  vtkFieldData* fd = last->GetFieldData();
  REQUIRE(fd != nullptr);
  auto value = [&](vtkFieldData* f, const char* name) {
    vtkDataArray* a = f->GetArray(name);
    REQUIRE(a != nullptr);
    return a->GetComponent(0, 0);
  };
  auto* stage = vtkStringArray::SafeDownCast(fd->GetAbstractArray("stage"));
  REQUIRE(stage != nullptr);
  CHECK(stage->GetValue(0) == "loading");
  CHECK(value(fd, "stage_number") == 4.0);
  CHECK(value(fd, "time") == Approx(sets.back().first).epsilon(1e-12));
  CHECK(value(fd, "time") == Approx(3.0 + value(fd, "load_factor")).epsilon(1e-12));
  CHECK(value(fd, "head_load_kN") == Approx(load).epsilon(1e-9));
  CHECK(value(fd, "head_settlement_mm") == Approx(settlement).epsilon(1e-9));
  // Every load's current value: the head load ramps with the stage (its resultant is the head
  // load, y up), the pile's weight and the soil's self-weight stay on in full; the pile's weight
  // is gamma_c L pi r^2 = 24 x 3 x pi x 0.135^2 kN.
  CHECK(value(fd, "load.head.fraction") == value(fd, "load_factor"));
  CHECK(value(fd, "load.head.Fy_kN") == Approx(-load).epsilon(1e-9));
  CHECK(value(fd, "load.pile_weight.fraction") == 1.0);
  CHECK(value(fd, "load.pile_weight.Fy_kN") == Approx(-24.0 * 3.0 * M_PI * 0.135 * 0.135).epsilon(1e-9));
  CHECK(value(fd, "load.self_weight.fraction") == 1.0);
  CHECK(fd->GetArray("load.fresh_concrete.fraction") == nullptr); // removed in the stage before
  // During boring the fresh-concrete pressure ramps in with the stage's load factor.
  for (const auto& [t, file] : sets)
    if (t > 1.01 && t < 2.0) { // 1.000001: the geostatic state once more (strictly increasing times)
      const auto b = read(file);
      CHECK(value(b->GetFieldData(), "load.fresh_concrete.fraction") == Approx(t - 1.0).epsilon(1e-12));
      CHECK(value(b->GetFieldData(), "load.self_weight.fraction") == 1.0);
    }
  // The first data set is the initial state: no stage yet, no head load.
  const auto first = read(sets.front().second);
  auto* stage0 = vtkStringArray::SafeDownCast(first->GetFieldData()->GetAbstractArray("stage"));
  REQUIRE(stage0 != nullptr);
  CHECK(stage0->GetValue(0) == "initial");
  CHECK(std::isnan(value(first->GetFieldData(), "head_load_kN")));
  // Named components: stress xx ... zx; interface traction shear/normal in the point cloud.
  vtkDataArray* stress = last->GetCellData()->GetArray("stress [kPa]");
  REQUIRE(stress != nullptr);
  REQUIRE(stress->GetComponentName(0) != nullptr);
  CHECK(std::string(stress->GetComponentName(0)) == "xx");
  CHECK(std::string(stress->GetComponentName(3)) == "xy");
  std::string vtp = sets.back().second;
  vtp.replace(vtp.rfind('_'), 1, "_ip_");
  vtp.replace(vtp.size() - 4, 4, ".vtp");
  auto pr = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  pr->SetFileName((out / vtp).string().c_str());
  pr->Update();
  vtkDataArray* tr = pr->GetOutput()->GetPointData()->GetArray("interface_traction [kPa]");
  REQUIRE(tr != nullptr);
  REQUIRE(tr->GetComponentName(1) != nullptr);
  CHECK(std::string(tr->GetComponentName(0)) == "shear");
  CHECK(std::string(tr->GetComponentName(1)) == "normal");
  CHECK(value(pr->GetOutput()->GetFieldData(), "load_factor") == value(fd, "load_factor"));
  fs::remove_all(out);
}

} // namespace test_run_output
