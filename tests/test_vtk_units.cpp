// Every array of the VTK output names its unit (issue 39): the shipped scenes are run and every
// array of every .vtu and .vtp they write is read back. A point or cell array is either a
// quantity named "name [unit]", with a unit the framework parses and spelt in the scene's units,
// or one of the integer codes; a field-data array follows the CSV columns' spelling
// ("head_load_kN") or is a count, a factor or a text. A scene without a pile head writes no pile
// field data.
#include "stratum/units.hpp"

#include <catch2/catch.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace test_vtk_units {

namespace fs = std::filesystem;

const std::set<std::string> codes{"domain", "set_id", "plastic", "interface_status"};
const std::set<std::string> bare_field_data{"time",        "stage", "stage_number", "step",
                                            "load_factor", "units", "domains",      "interface_status_names"};

/// The unit of "name [unit]", "" when the name has no bracketed unit.
std::string bracket_unit(const std::string& name) {
  static const std::regex re(R"(^(.+) \[([^\]]+)\]$)");
  std::smatch m;
  return std::regex_match(name, m, re) ? m[2].str() : std::string();
}

/// The unit of a field-data name "name_unit" ("head_load_kN", "Fy_kN_per_m"), "" when no split
/// of the name at an underscore leaves a unit the framework parses.
std::string suffix_unit(const std::string& name) {
  for (auto at = name.find('_'); at != std::string::npos; at = name.find('_', at + 1)) {
    std::string unit = name.substr(at + 1);
    for (auto p = unit.find("_per_"); p != std::string::npos; p = unit.find("_per_")) unit.replace(p, 5, "/");
    if (at > 0 && stratum::parse_unit(unit)) return unit;
  }
  return {};
}

struct Output {
  std::map<std::string, std::string> arrays; ///< point and cell arrays: name -> unit ("" for codes)
  std::set<std::string> field_data;
  int files = 0;
};

void read_arrays(vtkDataSet& data, const std::string& file, Output& out) {
  for (vtkFieldData* fd :
       {static_cast<vtkFieldData*>(data.GetPointData()), static_cast<vtkFieldData*>(data.GetCellData())})
    for (int i = 0; i < fd->GetNumberOfArrays(); ++i) {
      const std::string name = fd->GetArrayName(i);
      INFO(file << ": array \"" << name << "\"");
      const std::string unit = bracket_unit(name);
      if (unit.empty()) {
        CHECK(codes.count(name) == 1);
      } else {
        CHECK(stratum::parse_unit(unit).has_value());
      }
      if (vtkDataArray* a = fd->GetArray(i); a && a->GetNumberOfComponents() > 1)
        CHECK(a->GetComponentName(0) != nullptr); // xx..zx, x y z, shear normal, slip opening
      out.arrays[name] = unit;
    }
  vtkFieldData* fd = data.GetFieldData();
  for (int i = 0; i < fd->GetNumberOfArrays(); ++i) {
    const std::string name = fd->GetAbstractArray(i)->GetName();
    INFO(file << ": field data \"" << name << "\"");
    const bool bare = bare_field_data.count(name) == 1 || name.rfind("plastic_regimes_", 0) == 0 ||
                      (name.size() > 9 && name.compare(name.size() - 9, 9, ".fraction") == 0);
    CHECK((bare || !suffix_unit(name).empty()));
    out.field_data.insert(name);
  }
}

/// Runs `scene` (relative to the source tree) into a fresh folder and reads every VTK file it wrote.
Output run_and_read(const std::string& scene) {
  const fs::path out = fs::temp_directory_path() / ("stratum_vtk_units_" + fs::path(scene).stem().string() +
                                                    "_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(STRATUM_EXE) + " run " + STRATUM_SOURCE_DIR + "/" + scene + " --out " +
                          out.string() + " > " + out.string() + ".log 2>&1";
  INFO(cmd);
  REQUIRE(std::system(cmd.c_str()) == 0);
  Output o;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".vtu") {
      auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
      r->SetFileName(e.path().string().c_str());
      r->Update();
      REQUIRE(r->GetOutput() != nullptr);
      read_arrays(*r->GetOutput(), e.path().filename().string(), o);
      ++o.files;
    } else if (ext == ".vtp") {
      auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
      r->SetFileName(e.path().string().c_str());
      r->Update();
      REQUIRE(r->GetOutput() != nullptr);
      read_arrays(*r->GetOutput(), e.path().filename().string(), o);
      ++o.files;
    }
  }
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
  return o;
}

TEST_CASE("vtk units: every array of an axisymmetric scene without a pile head names its unit",
          "[output][units]") {
  const Output o = run_and_read("inputs/verification/lame_axisymmetric.toml");
  REQUIRE(o.files >= 4);
  CHECK(o.arrays.at("displacement [m]") == "m");
  CHECK(o.arrays.at("reaction [kN]") == "kN"); // the whole ring
  CHECK(o.arrays.at("stress [kPa]") == "kPa");
  CHECK(o.arrays.at("strain [-]") == "-");
  CHECK(o.arrays.count("stress") == 0);
  // no pile head: no pile field data
  for (const auto& name : o.field_data) {
    CHECK(name.rfind("head_load", 0) != 0);
    CHECK(name.rfind("head_settlement", 0) != 0);
  }
}

TEST_CASE("vtk units: the scene's own units name the arrays (N, mm)", "[output][units]") {
  const Output o = run_and_read("inputs/verification/lame_axisymmetric_n_mm.toml");
  CHECK(o.arrays.count("displacement [mm]") == 1);
  CHECK(o.arrays.count("reaction [N]") == 1);
  CHECK(o.arrays.count("stress [MPa]") == 1);
  CHECK(o.arrays.count("stress [kPa]") == 0);
}

TEST_CASE("vtk units: plane strain reactions are per metre, interface arrays", "[output][units]") {
  const Output ps = run_and_read("inputs/verification/lame_plane_strain.toml");
  CHECK(ps.arrays.count("reaction [kN/m]") == 1);
  const Output itf = run_and_read("inputs/verification/interface_column.toml");
  CHECK(itf.arrays.count("interface_traction [kPa]") == 1);
  CHECK(itf.arrays.count("interface_jump [m]") == 1);
  CHECK(itf.arrays.count("interface_status") == 1);
}

TEST_CASE("vtk units: pore pressure, history and the pile head's field data", "[output][units]") {
  const Output w = run_and_read("inputs/verification/terzaghi.toml");
  CHECK(w.arrays.count("p [kPa]") == 1);
  CHECK(w.arrays.count("pore_pressure [kPa]") == 1);
  CHECK(w.arrays.count("effective_stress [kPa]") == 1);
  const Output pile = run_and_read("inputs/loess_pile/cap.toml");
  CHECK(pile.field_data.count("head_load_kN") == 1);
  CHECK(pile.field_data.count("head_settlement_mm") == 1);
  const Output vm = run_and_read("inputs/verification/hill_cylinder.toml");
  CHECK(vm.arrays.count("eps_bar_p [-]") == 1);
}

} // namespace test_vtk_units
