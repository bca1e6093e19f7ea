// VTK XML output of a time series: .vtu (mesh + fields), .vtp (integration
// points) and .pvd collections, each written to a temporary file and renamed.
//
// Encoding: appended raw binary data (no base64), zlib-compressed blocks (level 1),
// 64-bit block headers. The most compact of the XML encodings that any current
// ParaView/VTK reader understands; for a 1e6-node quad mesh level 1 writes about the
// size of the default level 5 in half the time.
#include "stratum/vtk_output.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <string_view>
#include <system_error>

namespace stratum {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw Error("cannot write '" + path.string() + "': " + reason);
}

/// The temporary name of `final_path`: ".<name>.tmp" in the same directory.
fs::path temp_path_for(const fs::path& final_path) {
  return final_path.parent_path() / ("." + final_path.filename().string() + ".tmp");
}

/// Removes a file if it exists (never a directory that happens to have its name).
void remove_file(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return;
  fs::remove(path, ec);
}

/// Renames the finished temporary file over the final name; throws Error on failure.
void commit(const fs::path& tmp, const fs::path& final_path) {
  std::error_code ec;
  fs::rename(tmp, final_path, ec);
  if (ec) {
    remove_file(tmp);
    fail(final_path, ec.message());
  }
}

/// Collects the first error message a VTK object reports (instead of printing it).
struct ErrorCatcher {
  std::string message;

  static void on_error(vtkObject*, unsigned long, void* client, void* call) {
    auto* self = static_cast<ErrorCatcher*>(client);
    if (!self->message.empty() || call == nullptr) return;
    // VTK's text: "ERROR: In <source>, line <n>\n<Class> (<address>): <message>\n\n".
    std::string_view text(static_cast<const char*>(call));
    if (auto nl = text.find('\n'); nl != std::string_view::npos) text.remove_prefix(nl + 1);
    if (auto colon = text.find("): "); colon != std::string_view::npos) text.remove_prefix(colon + 3);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) {
      text.remove_suffix(1);
    }
    self->message = text.empty() ? std::string("VTK error") : std::string(text);
  }
};

/// Text of a vtkErrorCode (mirrors vtkErrorCode::GetStringFromErrorCode, which lives in
/// VTK::CommonMisc, a module the framework does not link directly).
std::string error_code_text(unsigned long code) {
  if (code < vtkErrorCode::FirstVTKErrorCode) return std::generic_category().message(static_cast<int>(code));
  switch (code) {
  case vtkErrorCode::FileNotFoundError:
    return "file not found";
  case vtkErrorCode::CannotOpenFileError:
    return "cannot open file";
  case vtkErrorCode::UnrecognizedFileTypeError:
    return "unrecognized file type";
  case vtkErrorCode::PrematureEndOfFileError:
    return "premature end of file";
  case vtkErrorCode::FileFormatError:
    return "file format error";
  case vtkErrorCode::NoFileNameError:
    return "no file name";
  case vtkErrorCode::OutOfDiskSpaceError:
    return "out of disk space";
  default:
    return "VTK error code " + std::to_string(code);
  }
}

/// Writes `data` with a configured VTK XML writer to `final_path` via a temporary file.
void write_vtk(vtkXMLWriter& writer, vtkDataObject* data, const fs::path& final_path) {
  const fs::path tmp = temp_path_for(final_path);
  const std::string tmp_name = tmp.string();

  ErrorCatcher catcher;
  vtkNew<vtkCallbackCommand> callback;
  callback->SetCallback(&ErrorCatcher::on_error);
  callback->SetClientData(&catcher);
  writer.AddObserver(vtkCommand::ErrorEvent, callback);
  // The pipeline executive reports a failed write again; keep that off the console too.
  vtkExecutive* executive = writer.GetExecutive();
  if (executive != nullptr) executive->AddObserver(vtkCommand::ErrorEvent, callback);

  writer.SetInputDataObject(data);
  writer.SetFileName(tmp_name.c_str());
  writer.SetDataModeToAppended();
  writer.EncodeAppendedDataOff();
  writer.SetHeaderTypeToUInt64();
  writer.SetCompressorTypeToZLib();
  writer.SetCompressionLevel(1); // about the size of the default level 5 at half the time

  const int ok = writer.Write();
  const unsigned long code = writer.GetErrorCode();
  writer.RemoveObservers(vtkCommand::ErrorEvent);
  if (executive != nullptr) executive->RemoveObservers(vtkCommand::ErrorEvent);
  writer.SetInputDataObject(nullptr);

  if (ok != 1 || code != vtkErrorCode::NoError) {
    remove_file(tmp);
    std::string reason = catcher.message;
    if (code != vtkErrorCode::NoError) {
      const std::string code_text = error_code_text(code);
      reason = reason.empty() ? code_text : reason + " (" + code_text + ")";
    }
    if (reason.empty()) reason = "VTK writer failed";
    fail(final_path, reason);
  }
  commit(tmp, final_path);
}

/// Writes a text file via a temporary file.
void write_text(const std::string& text, const fs::path& final_path) {
  const fs::path tmp = temp_path_for(final_path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      std::error_code ec;
      const bool is_dir = fs::is_directory(tmp, ec);
      fail(final_path, is_dir ? "temporary name is a directory" : "cannot open temporary file");
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      remove_file(tmp);
      fail(final_path, "write error");
    }
  }
  commit(tmp, final_path);
}

/// Shortest decimal text that reads back as the same double.
std::string format_double(double v) {
  std::array<char, 64> buf{};
  auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  if (ec != std::errc()) return "0";
  return std::string(buf.data(), end);
}

std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&apos;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

/// A ParaView collection file listing (time, relative file name) pairs.
std::string pvd_text(const std::vector<std::pair<double, std::string>>& entries) {
  std::string s = "<?xml version=\"1.0\"?>\n"
                  "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                  "  <Collection>\n";
  for (const auto& [t, file] : entries) {
    s += "    <DataSet timestep=\"" + format_double(t) + "\" group=\"\" part=\"0\" file=\"" +
         xml_escape(file) + "\"/>\n";
  }
  s += "  </Collection>\n</VTKFile>\n";
  return s;
}

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

} // namespace

VtkSeriesWriter::VtkSeriesWriter(std::string directory, std::string stem, bool background)
    : dir_(std::move(directory)), stem_(std::move(stem)), background_(background) {
  if (stem_.empty()) throw Error("VTK output: empty file name stem");
}

VtkSeriesWriter::~VtkSeriesWriter() {
  if (pending_.valid()) pending_.wait(); // an error here has nobody left to hear it
}

void VtkSeriesWriter::finish() {
  if (pending_.valid()) pending_.get(); // rethrows the background write's Error
}

std::string VtkSeriesWriter::pvd_path() const { return (fs::path(dir_) / (stem_ + ".pvd")).string(); }

void VtkSeriesWriter::write(const OutputStep& step) {
  if (step.mesh == nullptr) throw Error("VTK output: output step without a mesh");
  finish(); // the step before is on disk (or its error is thrown here)
  // Strictly increasing times: ParaView shows one data set per time value.
  const double time = !times_.empty() && !(step.time > times_.back()) ? times_.back() + 1e-6 : step.time;
  const Mesh& mesh = *step.mesh;

  // Validate everything before touching the disk.
  for (const OutputArray& f : step.point_fields) check_field(f, mesh.nodes.size(), "point", "nodes");
  for (const OutputArray& f : step.cell_fields) check_field(f, step.cells.size(), "cell", "cells");
  const auto num_ip = static_cast<std::size_t>(step.ip_coords.rows());
  for (const OutputArray& f : step.ip_fields) check_field(f, num_ip, "integration point", "points");

  const fs::path dir(dir_);
  {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) fail(dir, ec.message());
    if (!fs::is_directory(dir, ec)) fail(dir, "not a directory");
  }
  std::vector<double> times = times_;
  times.push_back(time);
  if (!background_) {
    write_files(step, times);
    times_ = std::move(times); // counted once its files are on disk
    return;
  }
  // The thread gets its own copies: the caller's step, mesh and times may change meanwhile.
  auto owned = std::make_shared<std::pair<OutputStep, Mesh>>(step, mesh);
  owned->first.mesh = &owned->second;
  times_ = times;
  pending_ = std::async(std::launch::async,
                        [this, owned, times = std::move(times)] { write_files(owned->first, times); });
}

void VtkSeriesWriter::write_files(const OutputStep& step, const std::vector<double>& times) const {
  const fs::path dir(dir_);
  const double time = times.back(); // step.time made strictly increasing
  const std::size_t k = times.size() - 1;
  const auto num_ip = static_cast<std::size_t>(step.ip_coords.rows());
  const std::string vtu_name = stem_ + "_" + std::to_string(k) + ".vtu";
  const std::string vtp_name = stem_ + "_ip_" + std::to_string(k) + ".vtp";

  {
    auto grid = make_grid(step, time);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    write_vtk(*writer, grid, dir / vtu_name);
  }

  if (num_ip > 0) {
    auto cloud = make_point_cloud(step, time);
    vtkNew<vtkXMLPolyDataWriter> writer;
    write_vtk(*writer, cloud, dir / vtp_name);
  } else {
    // No point cloud for this step: drop a stale file of an earlier run so the
    // collection below does not list it.
    remove_file(dir / vtp_name);
  }

  // Collections of every step so far (this one included).
  std::vector<std::pair<double, std::string>> grids, clouds;
  for (std::size_t i = 0; i <= k; ++i) {
    grids.emplace_back(times[i], stem_ + "_" + std::to_string(i) + ".vtu");
    std::string cloud = stem_ + "_ip_" + std::to_string(i) + ".vtp";
    std::error_code ec;
    if (fs::is_regular_file(dir / cloud, ec)) clouds.emplace_back(times[i], std::move(cloud));
  }
  write_text(pvd_text(grids), dir / (stem_ + ".pvd"));
  const fs::path ip_pvd = dir / (stem_ + "_ip.pvd");
  if (!clouds.empty()) {
    write_text(pvd_text(clouds), ip_pvd);
  } else {
    remove_file(ip_pvd);
  }
}

} // namespace stratum
