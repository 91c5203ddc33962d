/**
 * @class   vtkCellfxVolumeRepresentation
 * @brief   "cellfx Volume": unstructured and structured grids drawn by vtkCellfxVolumeMapper
 *
 * A volume representation like ParaView's own for unstructured grids, with two differences:
 * the cells reach the mapper as they are (tetrahedra, pyramids, wedges, hexahedra, voxels; a
 * structured grid becomes hexahedra; the leaves of a multiblock are merged into one grid with
 * shared points joined), where the stock representation cuts everything into tetrahedra; and
 * under MPI the cells on the boundaries between ranks are split along them, so that each rank
 * holds exactly its box of space and IceT's ordered compositing of the ranks' sorted images is
 * exact (the stock representation gives each boundary cell whole to one rank, which leaves
 * small ordering errors along the seams).
 *
 * Like the stock representation it asks the view for ordered compositing (data redistributed
 * on a k-d tree, images composited in visibility order), and shows the grid's surface while
 * interacting when the view asks for level of detail.
 */
#ifndef vtkCellfxVolumeRepresentation_h
#define vtkCellfxVolumeRepresentation_h

#include "CellfxVolumeRenderingModule.h" // for the export macro
#include "vtkNew.h"                      // for vtkNew
#include "vtkVolumeRepresentation.h"

class vtkCellfxVolumeMapper;
class vtkPolyDataMapper;
class vtkPVGeometryFilter;
class vtkUnstructuredGrid;

class CELLFXVOLUMERENDERING_EXPORT vtkCellfxVolumeRepresentation : public vtkVolumeRepresentation
{
public:
  static vtkCellfxVolumeRepresentation* New();
  vtkTypeMacro(vtkCellfxVolumeRepresentation, vtkVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int ProcessViewRequest(vtkInformationRequestKey* request_type, vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  ///@{
  /**
   * Forwarded to vtkCellfxVolumeMapper: the render path, the visibility sort and auto's
   * accepted error; which path the last frame on this process drew and why auto picked it.
   */
  void SetRenderPath(int path);
  int GetRenderPath();
  void SetSort(int sort);
  int GetSort();
  void SetAccuracy(double accuracy);
  double GetAccuracy();
  const char* GetChosenPath();
  const char* GetChoiceReason();
  ///@}

  ///@{
  /**
   * Under MPI, split the cells that cross the boundaries between ranks along them (default on),
   * so that each rank holds exactly its box and the ordered composite is exact. Off gives each
   * such cell whole to one rank, as ParaView's own volume representation does: faster to
   * redistribute, with small ordering errors along the seams.
   */
  void SetSplitBoundaryCells(bool split);
  vtkGetMacro(SplitBoundaryCells, bool);
  ///@}

  ///@{
  /**
   * What the mapper did in the last frame on this process (for tests and benchmarks): wall
   * milliseconds of the cellfx draw, cells drawn, mesh conversions since it was made.
   */
  double GetLastRenderMilliseconds();
  vtkIdType GetLastCellCount();
  int GetMeshConversions();
  ///@}

  vtkCellfxVolumeMapper* GetMapper() { return this->Mapper; }

protected:
  vtkCellfxVolumeRepresentation();
  ~vtkCellfxVolumeRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;
  void UpdateMapperParameters();

  bool SplitBoundaryCells = true;
  vtkNew<vtkCellfxVolumeMapper> Mapper;
  vtkNew<vtkUnstructuredGrid> Cells; // this process's input as one unstructured grid
  vtkNew<vtkPVGeometryFilter> LODGeometryFilter;
  vtkNew<vtkPolyDataMapper> LODMapper;

private:
  vtkCellfxVolumeRepresentation(const vtkCellfxVolumeRepresentation&) = delete;
  void operator=(const vtkCellfxVolumeRepresentation&) = delete;
};

#endif
