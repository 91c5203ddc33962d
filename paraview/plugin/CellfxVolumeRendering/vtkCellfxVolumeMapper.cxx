#include "vtkCellfxVolumeMapper.h"

#include <array>
#include <chrono>
#include <exception>
#include <memory>
#include <optional>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkLogger.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLCamera.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

#include "cellfx_vtk.hpp"
#include "fx/auto_path.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "fx/scanline_renderer.hpp"
#include "scanline_image.hpp"
#include "scene_depth.hpp"

namespace
{
// What the converted mesh was made from: objects and their modification times, and the
// model matrix baked into the points. A new object or a newer time means "changed".
struct GeometryKey
{
  std::array<const void*, 4> objects{};
  std::array<vtkMTimeType, 4> times{};
  std::array<double, 16> model{};
  bool operator==(const GeometryKey& o) const
  {
    return objects == o.objects && times == o.times && model == o.model;
  }
};

struct ScalarKey
{
  const void* array = nullptr;
  vtkMTimeType time = 0;
  bool cell_data = false;
  int component = 0;
  bool operator==(const ScalarKey& o) const
  {
    return array == o.array && time == o.time && cell_data == o.cell_data && component == o.component;
  }
};

struct TransferKey
{
  const void* color = nullptr;
  const void* opacity = nullptr;
  vtkMTimeType color_time = 0, opacity_time = 0;
  double unit_distance = 0.0;
  float lo = 0.0f, hi = 0.0f;
  bool operator==(const TransferKey& o) const
  {
    return color == o.color && opacity == o.opacity && color_time == o.color_time &&
      opacity_time == o.opacity_time && unit_distance == o.unit_distance && lo == o.lo && hi == o.hi;
  }
};

GeometryKey geometry_key(vtkUnstructuredGridBase* grid, vtkVolume* volume)
{
  GeometryKey key;
  if (auto* ug = vtkUnstructuredGrid::SafeDownCast(grid))
  {
    vtkObject* parts[4] = { ug->GetPoints(), ug->GetCells(), ug->GetCellTypesArray(),
      ug->GetCellGhostArray() };
    for (int i = 0; i < 4; ++i)
    {
      key.objects[i] = parts[i];
      key.times[i] = parts[i] ? parts[i]->GetMTime() : 0;
    }
  }
  else // another implementation of the unstructured-grid interface: any change counts
  {
    key.objects[0] = grid;
    key.times[0] = grid->GetMTime();
  }
  if (!volume->GetIsIdentity())
  {
    const double* m = &volume->GetMatrix()->Element[0][0];
    std::copy(m, m + 16, key.model.begin());
  }
  return key;
}

fx::RenderPath render_path(int value)
{
  switch (value)
  {
    case vtkCellfxVolumeMapper::ABSORPTION:
      return fx::RenderPath::Absorption;
    case vtkCellfxVolumeMapper::PCP_EXACT:
      return fx::RenderPath::PcpExact;
    case vtkCellfxVolumeMapper::MIP:
      return fx::RenderPath::Mip;
    default:
      return fx::RenderPath::AbsorptionExact;
  }
}

// The camera without VTK's explicit projection, for the scan-line renderer (which takes a view
// by fov or ortho height): only when that describes the same frustum for this viewport, i.e. it
// is on-axis with the viewport's aspect. None for an off-axis tile of a large screenshot.
std::optional<fx::Camera> plain_camera(const fx::Camera& view, int width, int height)
{
  if (!view.projection)
  {
    return view;
  }
  const glm::dmat4& p = *view.projection; // p[column][row]
  const bool perspective = p[2][3] != 0.0;
  const double off_x = perspective ? p[2][0] : p[3][0], off_y = perspective ? p[2][1] : p[3][1];
  const double aspect = p[1][1] / p[0][0];
  const double wanted = double(width) / double(height);
  if (std::abs(off_x) > 1e-9 || std::abs(off_y) > 1e-9 || std::abs(aspect - wanted) > 1e-6 * wanted)
  {
    return std::nullopt;
  }
  fx::Camera plain = view;
  plain.projection.reset();
  return plain;
}

fx::SortMethod sort_method(int value)
{
  switch (value)
  {
    case vtkCellfxVolumeMapper::MPVO:
      return fx::SortMethod::Mpvo;
    case vtkCellfxVolumeMapper::POWER:
      return fx::SortMethod::Power;
    case vtkCellfxVolumeMapper::CENTROID:
      return fx::SortMethod::Centroid;
    default:
      return fx::SortMethod::Xmpvo;
  }
}

// Reset + Push before cellfx draws, Pop after: VTK's cached GL state is re-applied, so VTK and
// GL agree whatever happened in between (cellfx restores the raw state itself as well).
class VtkStateBracket
{
public:
  explicit VtkStateBracket(vtkOpenGLState* state)
    : State(state)
  {
    this->State->Reset();
    this->State->Push();
  }
  ~VtkStateBracket() { this->State->Pop(); }
  VtkStateBracket(const VtkStateBracket&) = delete;
  VtkStateBracket& operator=(const VtkStateBracket&) = delete;

private:
  vtkOpenGLState* State;
};

constexpr const char* kFieldName = "scalars";
} // namespace

class vtkCellfxVolumeMapper::vtkInternals
{
public:
  std::unique_ptr<fx::CellRenderer> Renderer;
  // The converted mesh and transfer function, kept for the scan-line renderer (built on first
  // use from Mesh, which it refers to) and auto's calibration: a CPU copy of the mesh beside
  // the renderer's own.
  std::optional<fx::CellMesh> Mesh;
  std::optional<fx::TransferFunction> Tf;
  std::unique_ptr<fx::ScanlineRenderer> Scanline;
  cellfx_paraview::ScanlineImage ScanlineDraw; // its frame over VTK's framebuffer
  // auto's pick, kept until the mesh, field, transfer function, size, accuracy or sort changes
  // (the view may move: the costs depend on it far less than on the machine).
  struct AutoKey
  {
    std::optional<GeometryKey> geometry;
    std::optional<ScalarKey> scalars;
    std::optional<TransferKey> transfer;
    int width = 0, height = 0, sort = 0;
    double accuracy = 0.0;
    bool on_axis = true; // an off-axis tile is measured without the scan-line renderer
    bool operator==(const AutoKey& o) const
    {
      return geometry == o.geometry && scalars == o.scalars && transfer == o.transfer &&
        width == o.width && height == o.height && sort == o.sort && accuracy == o.accuracy &&
        on_axis == o.on_axis;
    }
  };
  std::optional<AutoKey> AutoFor;
  fx::PathChoice AutoChoice;
  std::string AutoReason; // the pick's line, with what was left out and why
  vtkWeakPointer<vtkOpenGLRenderWindow> Window; // whose context holds the GL objects
  cellfx_vtk::MeshConverter Converter;
  cellfx_paraview::SceneDepth Depth;
  std::optional<GeometryKey> Geometry;
  std::optional<ScalarKey> Scalars;
  std::optional<TransferKey> Transfer;
  std::size_t Cells = 0;
  fx::ScalarRange Range;
  std::string Reported; // the last message shown, so that a frame loop does not repeat it

  // AUTO (fx/auto_path.hpp): the pick for this mesh, field, transfer function, size, sort and
  // accuracy, measured on first use and kept; `reason` gets the line that says why.
  fx::AutoCandidate ChooseAutoPath(const fx::Camera& view, const std::optional<fx::Camera>& plain,
    int width, int height, int sort, double accuracy, std::string& reason)
  {
    vtkInternals& in = *this;
    const AutoKey key{ in.Geometry, in.Scalars, in.Transfer, width, height, sort, accuracy,
      plain.has_value() };
    if (in.AutoFor && *in.AutoFor == key)
    {
      reason = in.AutoReason;
      return in.AutoChoice.candidate;
    }
    fx::check_accuracy(accuracy, "CellfxAccuracy");
    // Emission–absorption only: what ParaView's volume property describes and IceT composites.
    std::vector<fx::AutoCandidate> candidates = fx::auto_candidates(fx::OpticalModel::EmissionAbsorption);
    std::string without_scanline;
    if (!plain)
    {
      without_scanline = "; scanline left out: an off-axis view (a tile of a large screenshot)";
    }
    else if (!in.Scanline)
    {
      try
      {
        in.Scanline = std::make_unique<fx::ScanlineRenderer>(*in.Mesh);
      }
      catch (const fx::Error& e)
      {
        without_scanline = std::string("; scanline left out: ") + e.what();
      }
    }
    if (!without_scanline.empty())
    {
      candidates.erase(candidates.begin()); // the scan-line renderer comes first
    }
    fx::CalibrationFrame frame;
    frame.mesh = &*in.Mesh;
    frame.field = &in.Mesh->scalars[0];
    frame.tf = &*in.Tf;
    frame.camera = plain ? *plain : view; // the GL paths take VTK's projection as it is
    frame.width = width;
    frame.height = height;
    frame.sort = sort_method(sort);
    const std::vector<fx::PathCost> costs =
      fx::measure_path_costs(frame, candidates, accuracy, in.Renderer.get(), in.Scanline.get());
    in.AutoChoice = fx::choose_path(costs, accuracy, width, height, "CellfxAccuracy");
    in.AutoFor = key;
    in.AutoReason = in.AutoChoice.reason + without_scanline;
    reason = in.AutoReason;
    vtkLog(INFO, "cellfx: " << reason);
    return in.AutoChoice.candidate;
  }

  // SCANLINE: the frame on the CPU, its image composited over the framebuffer in the viewport.
  void DrawScanline(const std::optional<fx::Camera>& plain, int x, int y, int width, int height)
  {
    if (!plain)
    {
      throw fx::Error("scanline: this view is off-axis (a tile of a large screenshot), which the "
                      "scan-line renderer does not take; use a GL path for it");
    }
    if (!this->Scanline)
    {
      this->Scanline = std::make_unique<fx::ScanlineRenderer>(*this->Mesh);
    }
    const fx::Image image =
      this->Scanline->render(*plain, width, height, this->Mesh->scalars[0], *this->Tf, {});
    this->ScanlineDraw.draw_over(image, x, y);
  }

  // Deletes the GL objects; the window's context must be current.
  void Release()
  {
    this->Depth.release();
    this->Renderer.reset();
    this->ScanlineDraw.release();
    this->Forget();
  }
  // The context is gone (its objects with it): keep nothing that refers to it.
  void Abandon()
  {
    static_cast<void>(this->Renderer.release()); // deleting would call GL without a context
    this->ScanlineDraw.abandon();
    this->Depth.abandon();
    this->Forget();
  }
  void Forget()
  {
    this->AutoFor.reset();
    this->Geometry.reset();
    this->Scalars.reset();
    this->Transfer.reset();
    this->Window = nullptr;
  }
};

vtkStandardNewMacro(vtkCellfxVolumeMapper);

vtkCellfxVolumeMapper::vtkCellfxVolumeMapper()
  : Internals(new vtkInternals)
{
}

vtkCellfxVolumeMapper::~vtkCellfxVolumeMapper()
{
  // VTK calls ReleaseGraphicsResources() while the window's context lives; what is left here
  // is deleted only if that context is current (at exit it may already be gone).
  vtkOpenGLRenderWindow* window = this->Internals->Window;
  if (window && window->IsCurrent())
  {
    this->Internals->Release();
  }
  else
  {
    this->Internals->Abandon();
  }
  delete this->Internals;
}

void vtkCellfxVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  if (this->Internals->Renderer && window && window == this->Internals->Window.GetPointer())
  {
    window->MakeCurrent();
    this->Internals->Release();
  }
  this->Superclass::ReleaseGraphicsResources(window);
}

void vtkCellfxVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  vtkInternals& in = *this->Internals;
  vtkUnstructuredGridBase* grid = this->GetInput();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  auto* camera = vtkOpenGLCamera::SafeDownCast(ren->GetActiveCamera());
  if (!grid || !window || !camera)
  {
    return;
  }
  if (in.Renderer && in.Window.GetPointer() != window)
  {
    if (vtkOpenGLRenderWindow* old = in.Window)
    {
      old->MakeCurrent();
      in.Release();
      window->MakeCurrent();
    }
    else
    {
      in.Abandon();
    }
  }

  try
  {
    // Which values to draw: the selected array, one component or the magnitude as the colour
    // map's vector mode says (as VTK's projected-tetrahedra mapper reads them).
    vtkVolumeProperty* property = vol->GetProperty();
    vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
    vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
    int cell_flag = 0;
    vtkDataArray* array = vtkDataArray::SafeDownCast(vtkAbstractMapper::GetScalars(
      grid, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cell_flag));
    if (cell_flag == 2)
    {
      throw fx::Error("scalars: field data has no value per point or cell");
    }
    cellfx_vtk::ScalarSelection selection;
    selection.array = array;
    selection.cell_data = cell_flag == 1;
    if (array && array->GetNumberOfComponents() > 1)
    {
      selection.component =
        color->GetVectorMode() == vtkScalarsToColors::MAGNITUDE ? -1 : color->GetVectorComponent();
    }
    const ScalarKey scalar_key{ array, array ? array->GetMTime() : 0, selection.cell_data,
      selection.component };

    // The mesh, converted when its geometry changed; new values alone are swapped in.
    const GeometryKey key = geometry_key(grid, vol);
    bool new_mesh = false;
    if (!in.Geometry || !(*in.Geometry == key))
    {
      cellfx_vtk::ConversionReport report;
      in.Scanline.reset(); // it refers to the mesh replaced here
      in.Mesh = in.Converter.convert(
        grid, vol->GetIsIdentity() ? nullptr : key.model.data(), selection, kFieldName, report);
      new_mesh = true;
      ++this->MeshConversions;
      in.Geometry = key;
      in.Scalars = scalar_key;
      in.Cells = in.Mesh->cell_count();
      in.Range = in.Cells ? fx::scalar_range(in.Mesh->scalars[0]) : fx::ScalarRange{};
      if (report.ghost_cells + report.flat_cells + report.unsupported_cells + report.flipped_cells)
      {
        vtkWarningMacro(<< "cellfx: " << report.summary());
      }
    }
    else if (!in.Scalars || !(*in.Scalars == scalar_key))
    {
      std::vector<float> values = in.Converter.scalars(grid, selection);
      in.Scalars = scalar_key;
      in.Range = in.Cells ? fx::scalar_range(fx::ScalarField{ kFieldName, values }) : fx::ScalarRange{};
      if (in.Renderer)
      {
        in.Renderer->set_scalars(values);
      }
      in.Mesh->scalars[0].values = std::move(values);
    }
    this->LastCellCount = static_cast<vtkIdType>(in.Cells);
    if (in.Cells == 0)
    {
      return;
    }

    // The transfer function, rebuilt when a function, the unit distance or the range changed.
    const TransferKey transfer_key{ color, opacity, color->GetMTime(), opacity->GetMTime(),
      property->GetScalarOpacityUnitDistance(0), in.Range.lo, in.Range.hi };
    bool new_tf = false;
    if (!in.Transfer || !(*in.Transfer == transfer_key) || new_mesh)
    {
      in.Tf = cellfx_vtk::transfer_function_from_vtk(
        color, opacity, transfer_key.unit_distance, in.Range.lo, in.Range.hi);
      in.Transfer = transfer_key;
      new_tf = true;
    }

    if (!in.Renderer)
    {
      in.Renderer = std::make_unique<fx::CellRenderer>(*in.Mesh, kFieldName, *in.Tf);
      in.Window = window;
    }
    else
    {
      if (new_mesh)
      {
        in.Renderer->set_mesh(*in.Mesh, kFieldName);
      }
      if (new_tf)
      {
        in.Renderer->set_transfer_function(*in.Tf);
      }
    }

    // VTK's own matrices (tiles and off-axis views included) and tiled viewport.
    vtkMatrix4x4 *wcvc = nullptr, *vcdc = nullptr, *wcdc = nullptr;
    vtkMatrix3x3* normals = nullptr;
    camera->GetKeyMatrices(ren, wcvc, normals, vcdc, wcdc);
    // The key matrices are transposed for OpenGL: their rows are GL's (and glm's) columns.
    const fx::Camera view = fx::Camera::from_matrices(
      glm::make_mat4(&wcvc->Element[0][0]), glm::make_mat4(&vcdc->Element[0][0]));
    int width = 0, height = 0, x = 0, y = 0;
    ren->GetTiledSizeAndOrigin(&width, &height, &x, &y);
    if (width <= 0 || height <= 0)
    {
      return;
    }
    const std::optional<fx::Camera> plain = plain_camera(view, width, height);

    const bool emission = this->RenderPath == PCP_EXACT || this->RenderPath == MIP;
    vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
    if (emission && controller && controller->GetNumberOfProcesses() > 1)
    {
      throw fx::Error(std::string(fx::render_path_name(render_path(this->RenderPath))) +
        " only adds light and leaves alpha at 0, which ParaView's parallel image compositing "
        "(IceT) takes for empty pixels, so with more than one process its image is lost: use "
        "absorption-exact, absorption, scanline or auto in parallel");
    }

    VtkStateBracket bracket(window->GetState());
    this->ChosenPath.clear(); // until a frame is drawn
    fx::AutoCandidate path = this->RenderPath == SCANLINE
      ? fx::kScanlineCandidate
      : fx::gl_candidate(render_path(this->RenderPath));
    if (this->RenderPath == AUTO)
    {
      path = in.ChooseAutoPath(view, plain, width, height, this->Sort, this->Accuracy, this->ChoiceReason);
    }
    if (this->RenderPath != AUTO)
    {
      this->ChoiceReason.clear();
    }

    const auto start = std::chrono::steady_clock::now();
    double sort_ms = 0.0;
    if (path.scanline)
    {
      in.DrawScanline(plain, x, y, width, height);
    }
    else
    {
      fx::CellRenderOptions options;
      options.sort = sort_method(this->Sort);
      std::string depth_source;
      options.scene_depth = in.Depth.texture_for_current_framebuffer(x, y, width, height, depth_source);
      const fx::CellRenderStats stats = in.Renderer->render(view, { x, y, width, height }, path.gl, options);
      sort_ms = stats.sort_ms;
      vtkDebugMacro(<< "cellfx: " << stats.cells << " cells, scene depth: " << depth_source);
    }
    this->ChosenPath = fx::candidate_name(path);
    this->LastRenderMilliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    this->LastSortMilliseconds = sort_ms;
    vtkDebugMacro(<< "cellfx: " << this->ChosenPath << ", " << this->LastRenderMilliseconds
                  << " ms (sort " << sort_ms << " ms)");
    in.Reported.clear();
  }
  catch (const std::exception& e)
  {
    if (in.Reported != e.what())
    {
      in.Reported = e.what();
      vtkErrorMacro(<< "cellfx: " << e.what());
    }
  }
}

void vtkCellfxVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RenderPath: " << this->RenderPath << " (last drawn: " << this->ChosenPath << ")\n";
  os << indent << "Accuracy: " << this->Accuracy << "\n";
  os << indent << "Sort: " << fx::sort_method_name(sort_method(this->Sort)) << "\n";
  os << indent << "MeshConversions: " << this->MeshConversions << "\n";
}
