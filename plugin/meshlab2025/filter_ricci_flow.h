// The filter for the plugin API of MeshLab 2021.05 to 2025.07 (FilterPlugin), which pymeshlab
// loads: dialog parameters in, results out, errors thrown as MLException. The work itself is in
// filter_computation.h; what this shares with the 2020.09 adapter is in meshlab_adapter.h.
#pragma once

#include <common/plugins/interfaces/filter_plugin.h>

class FilterRicciFlowPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

 public:
  enum { FP_RICCI_FLOW };

  FilterRicciFlowPlugin();

  QString pluginName() const override;
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction*) const override;
  FilterArity filterArity(const QAction*) const override;
  int getPreConditions(const QAction*) const override;
  int getRequirements(const QAction*) override;
  int postCondition(const QAction*) const override;
  RichParameterList initParameterList(const QAction*, const MeshModel& m) override;
  std::map<std::string, QVariant> applyFilter(const QAction* filter,
                                              const RichParameterList& parameters, MeshDocument& md,
                                              unsigned int& postConditionMask,
                                              vcg::CallBackPos* cb) override;
};
