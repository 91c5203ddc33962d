#include "vtkCellfxVolumeRepresentation.h"

#include "vtkAlgorithmOutput.h"
#include "vtkAppendFilter.h"
#include "vtkCellfxVolumeMapper.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPVGeometryFilter.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolumeProperty.h"

vtkStandardNewMacro(vtkCellfxVolumeRepresentation);

vtkCellfxVolumeRepresentation::vtkCellfxVolumeRepresentation()
{
  this->LODGeometryFilter->SetUseOutline(0);
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetLODMapper(this->LODMapper);
}

vtkCellfxVolumeRepresentation::~vtkCellfxVolumeRepresentation() = default;

void vtkCellfxVolumeRepresentation::SetRenderPath(int path)
{
  this->Mapper->SetRenderPath(path);
}
int vtkCellfxVolumeRepresentation::GetRenderPath()
{
  return this->Mapper->GetRenderPath();
}
void vtkCellfxVolumeRepresentation::SetSort(int sort)
{
  this->Mapper->SetSort(sort);
}
int vtkCellfxVolumeRepresentation::GetSort()
{
  return this->Mapper->GetSort();
}
void vtkCellfxVolumeRepresentation::SetAccuracy(double accuracy)
{
  this->Mapper->SetAccuracy(accuracy);
}
double vtkCellfxVolumeRepresentation::GetAccuracy()
{
  return this->Mapper->GetAccuracy();
}
const char* vtkCellfxVolumeRepresentation::GetChosenPath()
{
  return this->Mapper->GetChosenPath();
}
const char* vtkCellfxVolumeRepresentation::GetChoiceReason()
{
  return this->Mapper->GetChoiceReason();
}
void vtkCellfxVolumeRepresentation::SetSplitBoundaryCells(bool split)
{
  if (this->SplitBoundaryCells != split)
  {
    this->SplitBoundaryCells = split;
    this->MarkModified(); // the data are delivered again, redistributed the new way
  }
}
double vtkCellfxVolumeRepresentation::GetLastRenderMilliseconds()
{
  return this->Mapper->GetLastRenderMilliseconds();
}
vtkIdType vtkCellfxVolumeRepresentation::GetLastCellCount()
{
  return this->Mapper->GetLastCellCount();
}
int vtkCellfxVolumeRepresentation::GetMeshConversions()
{
  return this->Mapper->GetMeshConversions();
}

int vtkCellfxVolumeRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGridBase");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkStructuredGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkCellfxVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMath::UninitializeBounds(this->DataBounds);
  this->Cells->Initialize();
  if (inputVector[0]->GetNumberOfInformationObjects() == 1)
  {
    vtkAlgorithmOutput* port = this->GetInternalOutputPort();
    port->GetProducer()->Update(port->GetIndex());
    vtkDataObject* input = port->GetProducer()->GetOutputDataObject(port->GetIndex());
    if (auto* grid = vtkUnstructuredGrid::SafeDownCast(input))
    {
      this->Cells->ShallowCopy(grid);
    }
    else
    {
      // Structured grids become hexahedra; a multiblock's leaves one grid, their coincident
      // points joined so that the sort sees the faces blocks share.
      vtkNew<vtkAppendFilter> append;
      if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
      {
        vtkSmartPointer<vtkCompositeDataIterator> it;
        it.TakeReference(composite->NewIterator());
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
        {
          if (auto* leaf = vtkDataSet::SafeDownCast(it->GetCurrentDataObject()))
          {
            append->AddInputData(leaf);
          }
        }
        append->SetMergePoints(append->GetNumberOfInputConnections(0) > 1);
      }
      else if (auto* dataset = vtkDataSet::SafeDownCast(input))
      {
        append->AddInputData(dataset);
      }
      if (append->GetNumberOfInputConnections(0) > 0)
      {
        append->Update();
        this->Cells->ShallowCopy(append->GetOutput());
      }
    }
    this->Cells->RemoveGhostCells();
    if (this->Cells->GetNumberOfCells() > 0)
    {
      this->Cells->GetBounds(this->DataBounds);
    }
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

int vtkCellfxVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo))
  {
    return 0;
  }
  if (request_type == vtkPVView::REQUEST_UPDATE())
  {
    outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 1);
    vtkPVRenderView::SetPiece(inInfo, this, this->Cells);
    vtkPVRenderView::SetOrderedCompositingConfiguration(inInfo, this,
      vtkPVRenderView::DATA_IS_REDISTRIBUTABLE | vtkPVRenderView::USE_DATA_FOR_LOAD_BALANCING);
    // Each rank gets exactly its box: cells crossing a boundary are split along it (cellfx
    // draws the pieces, whatever their type), so the ordered composite has no seams.
    if (this->SplitBoundaryCells)
    {
      vtkPVRenderView::SetRedistributionModeToSplitBoundaryCells(inInfo, this);
    }
    else
    {
      vtkPVRenderView::SetRedistributionModeToUniquelyAssignBoundaryCells(inInfo, this);
    }
    vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
    vtkNew<vtkMatrix4x4> matrix;
    this->Actor->GetMatrix(matrix);
    vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds, matrix);
    this->Actor->SetMapper(nullptr);
  }
  else if (request_type == vtkPVView::REQUEST_UPDATE_LOD())
  {
    this->LODGeometryFilter->SetInputData(vtkPVView::GetPiece(inInfo, this));
    this->LODGeometryFilter->SetUseOutline(inInfo->Has(vtkPVRenderView::USE_OUTLINE_FOR_LOD()) ? 1 : 0);
    this->LODGeometryFilter->Update();
    vtkPVRenderView::SetPieceLOD(inInfo, this, this->LODGeometryFilter->GetOutputDataObject(0));
  }
  else if (request_type == vtkPVView::REQUEST_RENDER())
  {
    this->UpdateMapperParameters();
    this->Actor->SetEnableLOD(inInfo->Has(vtkPVRenderView::USE_LOD()) ? 1 : 0);
    vtkAlgorithmOutput* producer = vtkPVRenderView::GetPieceProducer(inInfo, this);
    if (producer &&
      vtkUnstructuredGridBase::SafeDownCast(producer->GetProducer()->GetOutputDataObject(0)))
    {
      this->Mapper->SetInputConnection(producer);
    }
    else
    {
      this->Actor->SetMapper(nullptr);
    }
    this->LODMapper->SetInputConnection(vtkPVRenderView::GetPieceProducerLOD(inInfo, this));
  }
  return 1;
}

void vtkCellfxVolumeRepresentation::UpdateMapperParameters()
{
  const char* name = nullptr;
  int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkInformation* info = this->GetInputArrayInformation(0);
  if (info && info->Has(vtkDataObject::FIELD_ASSOCIATION()) && info->Has(vtkDataObject::FIELD_NAME()))
  {
    name = info->Get(vtkDataObject::FIELD_NAME());
    association = info->Get(vtkDataObject::FIELD_ASSOCIATION());
  }
  this->Mapper->SelectScalarArray(name);
  this->Mapper->SetScalarMode(association == vtkDataObject::FIELD_ASSOCIATION_CELLS
      ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
      : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  this->LODMapper->SetScalarVisibility(name && name[0] ? 1 : 0);
  this->LODMapper->SelectColorArray(name);
  this->LODMapper->SetScalarMode(association == vtkDataObject::FIELD_ASSOCIATION_CELLS
      ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
      : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  // One component through the colour map (its vector mode picks it), as for the stock mappers.
  this->Property->SetIndependentComponents(true);
  this->Actor->SetMapper(this->Mapper);
}

bool vtkCellfxVolumeRepresentation::AddToView(vtkView* view)
{
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    rview->GetRenderer()->AddActor(this->Actor);
    return this->Superclass::AddToView(view);
  }
  return false;
}

bool vtkCellfxVolumeRepresentation::RemoveFromView(vtkView* view)
{
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    rview->GetRenderer()->RemoveActor(this->Actor);
    return this->Superclass::RemoveFromView(view);
  }
  return false;
}

void vtkCellfxVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mapper: " << this->Mapper << "\n";
}
