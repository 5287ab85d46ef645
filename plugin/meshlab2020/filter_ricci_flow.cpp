#include "filter_ricci_flow.h"

#include <cmath>

#include <vcg/complex/append.h>

#include "filter_computation.h"
#include "ricci/errors.h"

using namespace ricci::plugin;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// Progress in percent from the residual: log-linear between the first residual and the tolerance.
int percent(double first, double residual, double tolerance) {
  if (!(first > tolerance) || !(residual > 0)) return 99;
  const double done = std::log(first / residual) / std::log(first / tolerance);
  return std::max(0, std::min(99, static_cast<int>(100 * done)));
}

ParameterValues values_of(const RichParameterList& parameters) {
  ParameterValues values;
  for (const ParameterSpec& spec : parameter_specs()) {
    const QString name = q(spec.name);
    switch (spec.kind) {
      case ParameterSpec::Kind::Enum:
        values[spec.name] = parameters.getEnum(name);
        break;
      case ParameterSpec::Kind::Float:
        values[spec.name] = parameters.getFloat(name);
        break;
      case ParameterSpec::Kind::Int:
        values[spec.name] = parameters.getInt(name);
        break;
      case ParameterSpec::Kind::Bool:
        values[spec.name] = parameters.getBool(name) ? 1 : 0;
        break;
    }
  }
  return values;
}

}  // namespace

FilterRicciFlowPlugin::FilterRicciFlowPlugin() {
  typeList << FP_RICCI_FLOW;
  for (FilterIDType t : types()) actionList << new QAction(filterName(t), this);
}

QString FilterRicciFlowPlugin::pluginName() const {
  return "FilterRicciFlow";
}

QString FilterRicciFlowPlugin::filterName(FilterIDType) const {
  return q(filter_name());
}

QString FilterRicciFlowPlugin::filterInfo(FilterIDType) const {
  return q(filter_info());
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
  for (const ParameterSpec& spec : parameter_specs()) {
    const QString name = q(spec.name), label = q(spec.description), tip = q(spec.tooltip);
    switch (spec.kind) {
      case ParameterSpec::Kind::Enum: {
        QStringList labels;
        for (const auto& l : spec.enum_labels) labels << q(l);
        parameters.addParam(
            RichEnum(name, static_cast<int>(spec.default_value), labels, label, tip));
        break;
      }
      case ParameterSpec::Kind::Float:
        parameters.addParam(RichFloat(name, static_cast<float>(spec.default_value), label, tip));
        break;
      case ParameterSpec::Kind::Int:
        parameters.addParam(RichInt(name, static_cast<int>(spec.default_value), label, tip));
        break;
      case ParameterSpec::Kind::Bool:
        parameters.addParam(RichBool(name, spec.default_value != 0, label, tip));
        break;
    }
  }
}

bool FilterRicciFlowPlugin::applyFilter(QAction*, MeshDocument& md,
                                        const RichParameterList& parameters, vcg::CallBackPos* cb) {
  MeshModel& m = *md.mm();
  try {
    const FilterSettings settings = settings_from_values(values_of(parameters));
    const MeshInput input = read_mesh_input(m.cm, m.hasDataMask(MeshModel::MM_VERTQUALITY));
    double first = -1;
    const FilterComputation c = compute(input, settings, [&](const ricci::FlowProgress& p) {
      if (first < 0) first = p.residual;
      if (cb) cb(percent(first, p.residual, settings.tolerance), "Ricci flow: Newton iterations");
      return true;
    });
    // Everything succeeded: only now is the mesh changed.
    const WrittenComponents written = written_components(settings, c);
    int mask = 0;
    if (written.quality_and_color) mask |= MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    if (written.vertex_texcoord) mask |= MeshModel::MM_VERTTEXCOORD;
    if (written.wedge_texcoord) mask |= MeshModel::MM_WEDGTEXCOORD;
    m.updateDataMask(mask);
    write_results(m.cm, input, settings, c);
    if (written.layout_layer) {
      MeshModel* layer = md.addNewMesh("", m.label() + " (Ricci flow layout)", false);
      layer->updateDataMask(&m);
      vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(layer->cm, m.cm);
      place_at_layout(layer->cm, input, c);
      vcg::tri::UpdateBounding<CMeshO>::Box(layer->cm);
      vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(layer->cm);
    }
    for (const std::string& line : summary(input, settings, c)) Log("%s", line.c_str());
    return true;
  } catch (const ricci::Error& e) {
    errorMessage = QString("Ricci flow failed, the mesh is unchanged: ") + e.what();
    Log("%s", qUtf8Printable(errorMessage));
    return false;
  } catch (const std::exception& e) {
    errorMessage = QString("Ricci flow failed unexpectedly, the mesh is unchanged: ") + e.what();
    Log("%s", qUtf8Printable(errorMessage));
    return false;
  }
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterRicciFlowPlugin)
