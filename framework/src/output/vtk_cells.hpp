// The VTK data sets of one output step (framework/src/output/vtk_output.cpp writes them): the mesh
// with its point, cell and field data as an unstructured grid, the integration points as a
// point cloud. Internal to the framework.
#pragma once

#include "output/vtk_output.hpp"

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cstddef>

namespace stratum::vtk {

/// Throws Error when the field does not hold `tuples` tuples of its component count.
void check_field(const OutputArray& f, std::size_t tuples, const char* kind, const char* per);

/// The step's mesh (its active cells), point and cell fields and field data.
[[nodiscard]] vtkSmartPointer<vtkUnstructuredGrid> make_grid(const OutputStep& step, double time);

/// The step's integration points with their fields and the field data.
[[nodiscard]] vtkSmartPointer<vtkPolyData> make_point_cloud(const OutputStep& step, double time);

} // namespace stratum::vtk
