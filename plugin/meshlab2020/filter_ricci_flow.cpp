#include "filter_ricci_flow.h"

#include "meshlab_adapter.h"
#include "ricci/mesh/errors.h"

using namespace ricci::plugin;

FilterRicciFlowPlugin::FilterRicciFlowPlugin() {
  typeList << FP_RICCI_FLOW;
  for (FilterIDType t : types()) actionList << new QAction(filterName(t), this);
}

QString FilterRicciFlowPlugin::pluginName() const {
  return "FilterRicciFlow";
}

QString FilterRicciFlowPlugin::filterName(FilterIDType) const {
  return qstring(filter_name());
}

QString FilterRicciFlowPlugin::filterInfo(FilterIDType) const {
  return qstring(filter_info());
}

MeshFilterInterface::FilterClass FilterRicciFlowPlugin::getClass(QAction*) {
  return MeshFilterInterface::Texture;
}

MeshFilterInterface::FILTER_ARITY FilterRicciFlowPlugin::filterArity(QAction*) const {
  return SINGLE_MESH;
}

int FilterRicciFlowPlugin::getPreConditions(QAction*) const {
  return MeshModel::MM_FACENUMBER;
}

int FilterRicciFlowPlugin::postCondition(QAction*) const {
  return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTTEXCOORD |
         MeshModel::MM_WEDGTEXCOORD;
}

void FilterRicciFlowPlugin::initParameterSet(QAction*, MeshModel&, RichParameterList& parameters) {
  add_parameters(parameters, ParameterNaming::Script);
}

bool FilterRicciFlowPlugin::applyFilter(QAction*, MeshDocument& md,
                                        const RichParameterList& parameters, vcg::CallBackPos* cb) {
  try {
    std::vector<std::string> log;
    run_filter(md, values_of(parameters, ParameterNaming::Script), cb, log);
    for (const std::string& line : log) Log("%s", line.c_str());
    return true;
  } catch (const ricci::Error& e) {
    errorMessage = QString("Ricci flow failed, the mesh is unchanged: ") + e.what();
    Log("%s", qUtf8Printable(errorMessage));
    return false;
  } catch (const std::exception& e) {
    errorMessage = QString("Ricci flow failed unexpectedly, the mesh is unchanged: ") +
                   QString::fromStdString(ricci::failure_message(e));
    Log("%s", qUtf8Printable(errorMessage));
    return false;
  }
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterRicciFlowPlugin)
