#include "filter_ricci_flow.h"

#include "meshlab_adapter.h"
#include "ricci/mesh/errors.h"

using namespace ricci::plugin;

FilterRicciFlowPlugin::FilterRicciFlowPlugin() {
  typeList = {FP_RICCI_FLOW};
  for (ActionIDType t : types()) actionList.push_back(new QAction(filterName(t), this));
}

QString FilterRicciFlowPlugin::pluginName() const {
  return "FilterRicciFlow";
}

QString FilterRicciFlowPlugin::filterName(ActionIDType) const {
  return qstring(filter_name());
}

QString FilterRicciFlowPlugin::pythonFilterName(ActionIDType) const {
  return qstring(python_filter_name());
}

QString FilterRicciFlowPlugin::filterInfo(ActionIDType) const {
  return qstring(filter_info());
}

FilterPlugin::FilterClass FilterRicciFlowPlugin::getClass(const QAction*) const {
  return FilterPlugin::Texture;
}

FilterPlugin::FilterArity FilterRicciFlowPlugin::filterArity(const QAction*) const {
  return SINGLE_MESH;
}

int FilterRicciFlowPlugin::getPreConditions(const QAction*) const {
  return MeshModel::MM_FACENUMBER;
}

int FilterRicciFlowPlugin::getRequirements(const QAction*) {
  return MeshModel::MM_NONE;
}

int FilterRicciFlowPlugin::postCondition(const QAction*) const {
  return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTTEXCOORD |
         MeshModel::MM_WEDGTEXCOORD;
}

RichParameterList FilterRicciFlowPlugin::initParameterList(const QAction*, const MeshModel&) {
  RichParameterList parameters;
  add_parameters(parameters, ParameterNaming::Python);
  return parameters;
}

std::map<std::string, QVariant> FilterRicciFlowPlugin::applyFilter(
    const QAction*, const RichParameterList& parameters, MeshDocument& md, unsigned int&,
    vcg::CallBackPos* cb) {
  std::vector<std::string> log_lines;
  try {
    const FilterComputation c =
        run_filter(md, values_of(parameters, ParameterNaming::Python), cb, log_lines);
    for (const std::string& line : log_lines) log(line);
    // The numbers a script checks, returned by pymeshlab's apply_filter as a dict (pymeshlab
    // passes numbers only; geometry and layout kind are in the log).
    std::map<std::string, QVariant> out;
    for (const auto& [name, value] : ricci::result_numbers(c.run)) out[name] = value;
    return out;
  } catch (const ricci::Error& e) {
    throw MLException(QString("Ricci flow failed, the mesh is unchanged: ") + e.what());
  } catch (const MLException&) {
    throw;
  } catch (const std::exception& e) {
    throw MLException(QString("Ricci flow failed unexpectedly, the mesh is unchanged: ") +
                      QString::fromStdString(ricci::failure_message(e)));
  }
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterRicciFlowPlugin)
