// VTK XML output of a time series: .vtu (mesh + fields), .vtp (integration
// points) and .pvd collections, each written to a temporary file and renamed.
//
// Encoding: appended raw binary data (no base64), zlib-compressed blocks (level 1),
// 64-bit block headers. The most compact of the XML encodings that any current
// ParaView/VTK reader understands; for a 1e6-node quad mesh level 1 writes about the
// size of the default level 5 in half the time.
#include "output/vtk_output.hpp"
#include "files.hpp"
#include "output/vtk_cells.hpp"

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

#include <sys/resource.h>

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
  throw WriteError("cannot write '" + path.string() + "': " + reason);
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
    // One line: the executive's "Algorithm X returned failure for request: vtkInformation ..."
    // goes on with a dump of the request, which says nothing the error code does not.
    if (auto nl = text.find('\n'); nl != std::string_view::npos) text = text.substr(0, nl);
    if (text.rfind("Algorithm ", 0) == 0 && text.find("returned failure") != std::string_view::npos) return;
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
  case vtkErrorCode::OutOfDiskSpaceError: {
    // VTK says this of any failed write; with a file size limit set, that may be the cause.
    rlimit r{};
    if (::getrlimit(RLIMIT_FSIZE, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
      return "out of disk space, or the file size limit of " + std::to_string(r.rlim_cur / 1024) +
             " kB reached (ulimit -f)";
    return "out of disk space";
  }
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
  for (const OutputArray& f : step.point_fields) vtk::check_field(f, mesh.nodes.size(), "point", "nodes");
  for (const OutputArray& f : step.cell_fields) vtk::check_field(f, step.cells.size(), "cell", "cells");
  const auto num_ip = static_cast<std::size_t>(step.ip_coords.rows());
  for (const OutputArray& f : step.ip_fields) vtk::check_field(f, num_ip, "integration point", "points");

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
    auto grid = vtk::make_grid(step, time);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    write_vtk(*writer, grid, dir / vtu_name);
  }

  if (num_ip > 0) {
    auto cloud = vtk::make_point_cloud(step, time);
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
