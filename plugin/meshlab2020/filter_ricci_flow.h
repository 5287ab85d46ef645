// The filter for MeshLab 2020.09's plugin API (MeshFilterInterface): dialog parameters in,
// results out. The work itself is in filter_computation.h.
#pragma once

#include <common/interfaces.h>

class FilterRicciFlowPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  enum { FP_RICCI_FLOW };

  FilterRicciFlowPlugin();

  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction*) override;
  FILTER_ARITY filterArity(QAction*) const override;
  int getPreConditions(QAction*) const override;
  int postCondition(QAction*) const override;
  void initParameterSet(QAction*, MeshModel& m, RichParameterList& parameters) override;
  bool applyFilter(QAction* filter, MeshDocument& md, const RichParameterList& parameters,
                   vcg::CallBackPos* cb) override;
};
