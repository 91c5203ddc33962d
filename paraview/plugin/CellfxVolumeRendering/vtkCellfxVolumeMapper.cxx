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
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
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
  vtkWeakPointer<vtkOpenGLRenderWindow> Window; // whose context holds the GL objects
  cellfx_vtk::MeshConverter Converter;
  cellfx_paraview::SceneDepth Depth;
  std::optional<GeometryKey> Geometry;
  std::optional<ScalarKey> Scalars;
  std::optional<TransferKey> Transfer;
  std::size_t Cells = 0;
  fx::ScalarRange Range;
  std::string Reported; // the last message shown, so that a frame loop does not repeat it

  // Deletes the GL objects; the window's context must be current.
  void Release()
  {
    this->Depth.release();
    this->Renderer.reset();
    this->Forget();
  }
  // The context is gone (its objects with it): keep nothing that refers to it.
  void Abandon()
  {
    static_cast<void>(this->Renderer.release()); // deleting would call GL without a context
    this->Depth.abandon();
    this->Forget();
  }
  void Forget()
  {
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
    std::optional<fx::CellMesh> mesh;
    if (!in.Geometry || !(*in.Geometry == key))
    {
      cellfx_vtk::ConversionReport report;
      mesh = in.Converter.convert(
        grid, vol->GetIsIdentity() ? nullptr : key.model.data(), selection, kFieldName, report);
      ++this->MeshConversions;
      in.Geometry = key;
      in.Scalars = scalar_key;
      in.Cells = mesh->cell_count();
      in.Range = in.Cells ? fx::scalar_range(mesh->scalars[0]) : fx::ScalarRange{};
      if (report.ghost_cells + report.flat_cells + report.unsupported_cells + report.flipped_cells)
      {
        vtkWarningMacro(<< "cellfx: " << report.summary());
      }
    }
    else if (!in.Scalars || !(*in.Scalars == scalar_key))
    {
      const std::vector<float> values = in.Converter.scalars(grid, selection);
      in.Scalars = scalar_key;
      in.Range = in.Cells ? fx::scalar_range(fx::ScalarField{ kFieldName, values }) : fx::ScalarRange{};
      if (in.Renderer)
      {
        in.Renderer->set_scalars(values);
      }
    }
    this->LastCellCount = static_cast<vtkIdType>(in.Cells);
    if (in.Cells == 0)
    {
      return;
    }

    // The transfer function, rebuilt when a function, the unit distance or the range changed.
    const TransferKey transfer_key{ color, opacity, color->GetMTime(), opacity->GetMTime(),
      property->GetScalarOpacityUnitDistance(0), in.Range.lo, in.Range.hi };
    std::optional<fx::TransferFunction> tf;
    if (!in.Transfer || !(*in.Transfer == transfer_key) || mesh)
    {
      tf = cellfx_vtk::transfer_function_from_vtk(
        color, opacity, transfer_key.unit_distance, in.Range.lo, in.Range.hi);
      in.Transfer = transfer_key;
    }

    if (!in.Renderer)
    {
      in.Renderer = std::make_unique<fx::CellRenderer>(*mesh, kFieldName, *tf);
      in.Window = window;
    }
    else
    {
      if (mesh)
      {
        in.Renderer->set_mesh(*mesh, kFieldName);
      }
      if (tf)
      {
        in.Renderer->set_transfer_function(*tf);
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

    const bool emission = this->RenderPath == PCP_EXACT || this->RenderPath == MIP;
    vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
    if (emission && controller && controller->GetNumberOfProcesses() > 1)
    {
      throw fx::Error(std::string(fx::render_path_name(render_path(this->RenderPath))) +
        " only adds light and leaves alpha at 0, which ParaView's parallel image compositing "
        "(IceT) takes for empty pixels, so with more than one process its image is lost: use "
        "absorption-exact or absorption in parallel");
    }

    VtkStateBracket bracket(window->GetState());
    fx::CellRenderOptions options;
    options.sort = sort_method(this->Sort);
    std::string depth_source;
    options.scene_depth = in.Depth.texture_for_current_framebuffer(x, y, width, height, depth_source);
    const auto start = std::chrono::steady_clock::now();
    const fx::CellRenderStats stats =
      in.Renderer->render(view, { x, y, width, height }, render_path(this->RenderPath), options);
    this->LastRenderMilliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    this->LastSortMilliseconds = stats.sort_ms;
    vtkDebugMacro(<< "cellfx: " << stats.cells << " cells, " << this->LastRenderMilliseconds
                  << " ms (sort " << stats.sort_ms << " ms), scene depth: " << depth_source);
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
  os << indent << "RenderPath: " << fx::render_path_name(render_path(this->RenderPath)) << "\n";
  os << indent << "Sort: " << fx::sort_method_name(sort_method(this->Sort)) << "\n";
  os << indent << "MeshConversions: " << this->MeshConversions << "\n";
}
