/**
 * @class   vtkCellfxVolumeMapper
 * @brief   volume mapper drawing tetrahedra, pyramids, wedges and hexahedra with cellfx
 *
 * Renders the unstructured grid it is given with one of cellfx's paths (docs/paraview.md):
 * absorption-exact (default; cells sorted back to front, exact ray segments and a
 * pre-integration table), absorption (the same order, Max, Williams & Silva's projected
 * subdivision), pcp-exact (emission only, no sort), mip (maximum intensity), scanline (the
 * exact CPU scan-line renderer, its image composited over the framebuffer) or auto: the
 * fastest of scanline, absorption-exact and absorption that meets Accuracy, measured on this
 * process's cells and view (fx/auto_path.hpp) and kept until the mesh, the transfer function,
 * the viewport's size or the accuracy changes. The cells are drawn as they are, not cut into
 * tetrahedra.
 *
 * Colour and opacity come from the volume property as VTK's unstructured-grid mappers read
 * them: colour = the colour map at s, extinction per unit length = the scalar opacity at s
 * divided by the scalar-opacity unit distance (cellfx_vtk.hpp). The mesh is converted once and
 * kept until the input's geometry changes (a new scalar array only replaces the values); the
 * transfer function is rebuilt when a function, the unit distance or the scalar range changes.
 *
 * Render() draws into the framebuffer VTK has bound, in the renderer's tiled viewport, with the
 * camera's own view and projection matrices (vtkOpenGLCamera::GetKeyMatrices, so off-axis
 * tiles of a large screenshot come out seamless), stopped by the depth of the opaque geometry
 * drawn before it. cellfx restores every GL state it changes; the mapper brackets the call
 * with vtkOpenGLState::Reset/Push/Pop so that VTK's state cache agrees with GL afterwards.
 * Needs an OpenGL 4.5 core context.
 */
#ifndef vtkCellfxVolumeMapper_h
#define vtkCellfxVolumeMapper_h

#include "CellfxVolumeRenderingModule.h" // for the export macro
#include "vtkUnstructuredGridVolumeMapper.h"

#include <string> // for ChosenPath

class vtkRenderer;
class vtkVolume;
class vtkWindow;

class CELLFXVOLUMERENDERING_EXPORT vtkCellfxVolumeMapper : public vtkUnstructuredGridVolumeMapper
{
public:
  static vtkCellfxVolumeMapper* New();
  vtkTypeMacro(vtkCellfxVolumeMapper, vtkUnstructuredGridVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum RenderPathValues
  {
    ABSORPTION_EXACT = 0,
    ABSORPTION = 1,
    PCP_EXACT = 2,
    MIP = 3,
    SCANLINE = 4,
    AUTO = 5
  };
  ///@{
  /**
   * The cellfx render path (RenderPathValues). Default ABSORPTION_EXACT.
   */
  vtkSetClampMacro(RenderPath, int, ABSORPTION_EXACT, AUTO);
  vtkGetMacro(RenderPath, int);
  ///@}

  ///@{
  /**
   * AUTO: the accepted mean error per pixel, a share of the picture's peak (fx/auto_path.hpp).
   * Default 1e-3 (the exact paths and scanline); 4e-3 lets absorption in. A value outside
   * [1e-6, 1] is reported by name when drawing and nothing is drawn.
   */
  vtkSetMacro(Accuracy, double);
  vtkGetMacro(Accuracy, double);
  ///@}

  /**
   * The path the last Render() drew with ("scanline", "absorption-exact", ...; "" before the
   * first), and for AUTO the line saying why it was picked (what each candidate cost).
   */
  const char* GetChosenPath() { return this->ChosenPath.c_str(); }
  const char* GetChoiceReason() { return this->ChoiceReason.c_str(); }

  enum SortValues
  {
    XMPVO = 0,
    MPVO = 1,
    POWER = 2,
    CENTROID = 3
  };
  ///@{
  /**
   * The visibility sort of the absorption paths (SortValues). Default XMPVO, exact for convex
   * and non-convex meshes of convex cells; CENTROID is approximate (docs/visibility_sort.md).
   */
  vtkSetClampMacro(Sort, int, XMPVO, CENTROID);
  vtkGetMacro(Sort, int);
  ///@}

  ///@{
  /**
   * What the last Render() did: wall milliseconds of the cellfx call, of which the visibility
   * sort; cells drawn; and how many times the mesh has been converted since this mapper was
   * made (stays at 1 while only the camera moves).
   */
  vtkGetMacro(LastRenderMilliseconds, double);
  vtkGetMacro(LastSortMilliseconds, double);
  vtkGetMacro(LastCellCount, vtkIdType);
  vtkGetMacro(MeshConversions, int);
  ///@}

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkCellfxVolumeMapper();
  ~vtkCellfxVolumeMapper() override;

  int RenderPath = ABSORPTION_EXACT;
  int Sort = XMPVO;
  double Accuracy = 1e-3;
  std::string ChosenPath;
  std::string ChoiceReason;
  double LastRenderMilliseconds = 0.0;
  double LastSortMilliseconds = 0.0;
  vtkIdType LastCellCount = 0;
  int MeshConversions = 0;

private:
  vtkCellfxVolumeMapper(const vtkCellfxVolumeMapper&) = delete;
  void operator=(const vtkCellfxVolumeMapper&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
