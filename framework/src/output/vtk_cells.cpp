// The VTK data sets of one output step: cells and points, the field arrays, the field data
// (framework/src/output/vtk_cells.hpp).
#include "output/vtk_cells.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include <array>
#include <string>

namespace stratum::vtk {

/// Throws Error when the field does not hold `tuples` tuples of its component count.
void check_field(const OutputArray& f, std::size_t tuples, const char* kind, const char* per) {
  if (f.name.empty()) throw Error(std::string("VTK output: a ") + kind + " field has no name");
  if (f.components < 1) {
    throw Error(std::string("VTK output: ") + kind + " field '" + f.name + "' has " +
                std::to_string(f.components) + " components");
  }
  const std::size_t expected = tuples * static_cast<std::size_t>(f.components);
  if (f.values.size() != expected) {
    throw Error(std::string("VTK output: ") + kind + " field '" + f.name + "' has " +
                std::to_string(f.values.size()) + " values, expected " + std::to_string(tuples) + " " + per +
                " x " + std::to_string(f.components) + " components = " + std::to_string(expected));
  }
}

namespace {

vtkSmartPointer<vtkDoubleArray> make_array(const OutputArray& f) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(f.name.c_str());
  a->SetNumberOfComponents(f.components);
  const auto tuples = static_cast<vtkIdType>(f.values.size() / static_cast<std::size_t>(f.components));
  a->SetNumberOfTuples(tuples);
  if (!f.values.empty())
    std::copy(f.values.begin(), f.values.end(), a->WritePointer(0, a->GetNumberOfValues()));
  for (std::size_t c = 0; c < f.component_names.size() && c < static_cast<std::size_t>(f.components); ++c)
    a->SetComponentName(static_cast<vtkIdType>(c), f.component_names[c].c_str());
  return a;
}

/// The step's field data: one-tuple arrays (ParaView: "OutputArray Data").
void add_field_data(vtkDataObject& data, const OutputStep& step, double time) {
  vtkFieldData* fd = data.GetFieldData();
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName("time");
    a->InsertNextValue(time);
    fd->AddArray(a);
  }
  for (const auto& [name, v] : step.values) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(v);
    fd->AddArray(a);
  }
  for (const auto& [name, v] : step.texts) {
    vtkNew<vtkStringArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(v);
    fd->AddArray(a);
  }
  for (const auto& [name, list] : step.text_lists) {
    vtkNew<vtkStringArray> a;
    a->SetName(name.c_str());
    for (const auto& v : list) a->InsertNextValue(v);
    fd->AddArray(a);
  }
}

/// Points with z = 0 from n 2-D coordinates given by `xy(i, c)`.
template <class XY> vtkSmartPointer<vtkPoints> make_points(vtkIdType n, XY&& xy) {
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(n);
  double* p = coords->WritePointer(0, 3 * n);
  for (vtkIdType i = 0; i < n; ++i) {
    p[3 * i] = xy(i, 0);
    p[3 * i + 1] = xy(i, 1);
    p[3 * i + 2] = 0.0;
  }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(coords);
  return points;
}

/// The VTK type and point list of one cell; returns the number of points written to `ids`.
int vtk_cell(const Cell& c, int index, std::size_t num_nodes, unsigned char& type,
             std::array<vtkIdType, 8>& ids) {
  for (int s = 0; s < 8; ++s) {
    const int n = c.nodes[s];
    if (n >= 0 && static_cast<std::size_t>(n) >= num_nodes) {
      throw Error("VTK output: cell " + std::to_string(index) + " references missing node " +
                  std::to_string(n));
    }
  }
  const unsigned shape = c.shape();
  if (c.type == CellType::node_pair) { // the two coincident nodes (slots 2, 3 are geometry only)
    type = VTK_LINE;
    ids[0] = c.nodes[0], ids[1] = c.nodes[1];
    return 2;
  }
  if (c.type == CellType::line_interface && shape == 0x5Fu) { // 3 + 3 nodes
    type = VTK_QUADRATIC_LINEAR_QUAD;
    for (int s = 0; s < 4; ++s) ids[s] = c.nodes[s];
    ids[4] = c.nodes[4], ids[5] = c.nodes[6];
    return 6;
  }
  if (shape == 0x07u || shape == 0x77u) { // triangle: corners 0-2, midside 4 (0-1), 5 (1-2), 6 (2-0)
    type = shape == 0x07u ? VTK_TRIANGLE : VTK_QUADRATIC_TRIANGLE;
    ids[0] = c.nodes[0], ids[1] = c.nodes[1], ids[2] = c.nodes[2];
    if (shape == 0x07u) return 3;
    ids[3] = c.nodes[4], ids[4] = c.nodes[5], ids[5] = c.nodes[6];
    return 6;
  }
  if ((shape & 0x0Fu) != 0x0Fu) {
    throw Error("VTK output: cell " + std::to_string(index) + " lacks a corner node");
  }
  if (shape == 0x0Fu || shape == 0xFFu) {
    type = shape == 0x0Fu ? VTK_QUAD : VTK_QUADRATIC_QUAD;
    const int n = shape == 0x0Fu ? 4 : 8;
    for (int s = 0; s < n; ++s) ids[s] = c.nodes[s];
    return n;
  }
  // Transition quad: corner k, then the midside node of edge k -> k+1 when present.
  type = VTK_POLYGON;
  int n = 0;
  for (int k = 0; k < 4; ++k) {
    ids[n++] = c.nodes[k];
    if (c.nodes[4 + k] >= 0) ids[n++] = c.nodes[4 + k];
  }
  return n;
}

} // namespace

vtkSmartPointer<vtkUnstructuredGrid> make_grid(const OutputStep& step, double time) {
  const Mesh& mesh = *step.mesh;
  const auto num_nodes = static_cast<vtkIdType>(mesh.nodes.size());
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(make_points(num_nodes, [&](vtkIdType i, int c) { return mesh.nodes[i][c]; }));

  const auto num_cells = static_cast<vtkIdType>(step.cells.size());
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfTuples(num_cells);
  unsigned char* type_ptr = types->WritePointer(0, num_cells);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(num_cells + 1);
  vtkIdType* offset_ptr = offsets->WritePointer(0, num_cells + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(8 * num_cells); // upper bound, shrunk below
  vtkIdType* conn_ptr = connectivity->WritePointer(0, 8 * num_cells);

  vtkIdType used = 0;
  offset_ptr[0] = 0;
  std::array<vtkIdType, 8> ids{};
  for (vtkIdType k = 0; k < num_cells; ++k) {
    const int index = step.cells[static_cast<std::size_t>(k)];
    if (index < 0 || static_cast<std::size_t>(index) >= mesh.cells.size()) {
      throw Error("VTK output: cell index " + std::to_string(index) + " is not a cell of the mesh (" +
                  std::to_string(mesh.cells.size()) + " cells)");
    }
    const int n =
        vtk_cell(mesh.cells[static_cast<std::size_t>(index)], index, mesh.nodes.size(), type_ptr[k], ids);
    std::copy_n(ids.begin(), n, conn_ptr + used);
    used += n;
    offset_ptr[k + 1] = used;
  }
  connectivity->SetNumberOfTuples(used);
  connectivity->Squeeze();

  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  grid->SetCells(types, cells);

  for (const OutputArray& f : step.point_fields) grid->GetPointData()->AddArray(make_array(f));
  for (const OutputArray& f : step.cell_fields) grid->GetCellData()->AddArray(make_array(f));
  add_field_data(*grid, step, time);
  return grid;
}

vtkSmartPointer<vtkPolyData> make_point_cloud(const OutputStep& step, double time) {
  const auto n = static_cast<vtkIdType>(step.ip_coords.rows());
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(make_points(n, [&](vtkIdType i, int c) { return step.ip_coords(i, c); }));

  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(n + 1);
  vtkIdType* offset_ptr = offsets->WritePointer(0, n + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(n);
  vtkIdType* conn_ptr = connectivity->WritePointer(0, n);
  for (vtkIdType i = 0; i < n; ++i) {
    offset_ptr[i] = i;
    conn_ptr[i] = i;
  }
  offset_ptr[n] = n;
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, connectivity);
  cloud->SetVerts(verts);

  for (const OutputArray& f : step.ip_fields) cloud->GetPointData()->AddArray(make_array(f));
  add_field_data(*cloud, step, time);
  return cloud;
}

} // namespace stratum::vtk
