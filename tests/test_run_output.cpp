// The default scene, run as `tools/run` runs it, writes a .pvd collection whose
// files VTK's XML readers read back with the right numbers.
#include <catch2/catch.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

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
  vtkDataArray* u = grid->GetPointData()->GetArray("displacement");
  REQUIRE(u != nullptr);
  REQUIRE(u->GetNumberOfComponents() == 3);
  // The largest radial displacement sits on the inner face: u(a) of the Lamé solution.
  double umax = 0;
  for (vtkIdType i = 0; i < u->GetNumberOfTuples(); ++i) umax = std::max(umax, u->GetComponent(i, 0));
  const double exact = (1 + 0.3) * 1.0 / (1000.0 * 3.0) * ((1 - 0.6) * 1.0 + 4.0);
  CHECK(std::abs(umax - exact) / exact < 1e-3);
  vtkDataArray* stress = grid->GetCellData()->GetArray("stress");
  REQUIRE(stress != nullptr);
  CHECK(stress->GetNumberOfComponents() == 6);
  CHECK(grid->GetCellData()->GetArray("set_id") != nullptr);

  auto pr = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  pr->SetFileName((out / "lame_axisymmetric_ip_1.vtp").string().c_str());
  pr->Update();
  CHECK(pr->GetOutput()->GetNumberOfPoints() == 16 * 9);
  CHECK(pr->GetOutput()->GetPointData()->GetArray("stress") != nullptr);
  fs::remove_all(out);
}
