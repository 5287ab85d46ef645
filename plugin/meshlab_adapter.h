// What the MeshLab adapters share, as templates over MeshLab's types (included after MeshLab's own
// headers, by each adapter only): the dialog from the parameter table, the values back out of it,
// and one run of the filter on the current mesh of a document. Both plugin APIs (2020.09's
// MeshFilterInterface, 2021.05+'s FilterPlugin) spell these types and calls alike.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include <vcg/complex/append.h>
#include <QString>
#include <QStringList>

#include "filter_computation.h"
#include "filter_settings.h"
#include "ricci/report/report.h"

namespace ricci::plugin {

inline QString qstring(const std::string& s) {
  return QString::fromStdString(s);
}

//! Which names the dialog uses: the .mlx names (MeshLab 2020.09 scripts) or the snake-case names
//! pymeshlab shows as keyword arguments (MeshLab 2021.05 and later).
enum class ParameterNaming { Script, Python };

inline QString parameter_name(const ParameterSpec& spec, ParameterNaming naming) {
  return qstring(naming == ParameterNaming::Script ? spec.name : python_parameter_name(spec.name));
}

//! Adds the parameter table to a RichParameterList.
template <class ParameterList>
void add_parameters(ParameterList& parameters, ParameterNaming naming) {
  for (const ParameterSpec& spec : parameter_specs()) {
    const QString name = parameter_name(spec, naming);
    const QString label = qstring(spec.description), tip = qstring(spec.tooltip);
    switch (spec.kind) {
      case ParameterSpec::Kind::Enum: {
        QStringList labels;
        for (const auto& l : spec.enum_labels) labels << qstring(l);
        parameters.addParam(
            RichEnum(name, static_cast<int>(spec.default_value), labels, label, tip));
        break;
      }
      case ParameterSpec::Kind::Float:
        parameters.addParam(RichFloat(name, spec.default_value, label, tip));
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

//! The chosen values, by the parameter table's (script) names.
template <class ParameterList>
ParameterValues values_of(const ParameterList& parameters, ParameterNaming naming) {
  ParameterValues values;
  for (const ParameterSpec& spec : parameter_specs()) {
    const QString name = parameter_name(spec, naming);
    switch (spec.kind) {
      case ParameterSpec::Kind::Enum:
        values[spec.name] = parameters.getEnum(name);
        break;
      case ParameterSpec::Kind::Float:
        values[spec.name] = static_cast<double>(parameters.getFloat(name));
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

//! Progress in percent from the residual: log-linear between the first residual and the tolerance.
inline int progress_percent(double first, double residual, double tolerance) {
  if (!(first > tolerance) || !(residual > 0)) return 99;
  const double done = std::log(first / residual) / std::log(first / tolerance);
  return std::max(0, std::min(99, static_cast<int>(100 * done)));
}

//! Runs the filter on the document's current mesh and writes the results (and the layout layer)
//! only when everything succeeded. Returns the computation for the log and the caller's outputs.
//! \throws ricci::Error (the mesh is then unchanged), std::exception for the unexpected.
template <class Document, class CallBack>
FilterComputation run_filter(Document& md, const ParameterValues& values, CallBack* cb,
                             std::vector<std::string>& log) {
  auto& m = *md.mm();
  using Model = std::remove_reference_t<decltype(m)>;
  using Mesh = std::remove_reference_t<decltype(m.cm)>;
  const FilterSettings settings = settings_from_values(values);
  const MeshInput input =
      read_mesh_input(m.cm, m.hasDataMask(Model::MM_VERTQUALITY), settings.repair);
  double first = -1;
  FilterComputation c = compute(input, settings, [&](const FlowProgress& p) {
    if (first < 0) first = p.residual;
    if (cb) cb(progress_percent(first, p.residual, settings.tolerance), "Ricci flow");
    return true;
  });
  // Everything succeeded: only now is the mesh changed.
  const WrittenComponents written = written_components(settings, c);
  int mask = 0;
  if (written.quality_and_color) mask |= Model::MM_VERTQUALITY | Model::MM_VERTCOLOR;
  if (written.vertex_texcoord) mask |= Model::MM_VERTTEXCOORD;
  if (written.wedge_texcoord) mask |= Model::MM_WEDGTEXCOORD;
  m.updateDataMask(mask);
  write_results(m.cm, input, settings, c);
  if (c.rebuilds(input)) {  // the repairs changed faces: adjacency and normals are stale
    m.clearDataMask(Model::MM_FACEFACETOPO | Model::MM_VERTFACETOPO);
    vcg::tri::UpdateNormal<Mesh>::PerVertexNormalizedPerFaceNormalized(m.cm);
  }
  if (written.layout_layer) {
    Model* layer = md.addNewMesh("", m.label() + " (Ricci flow layout)", false);
    layer->updateDataMask(&m);
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(layer->cm, m.cm);
    place_at_layout(layer->cm, c);
    vcg::tri::UpdateBounding<Mesh>::Box(layer->cm);
    vcg::tri::UpdateNormal<Mesh>::PerVertexNormalizedPerFaceNormalized(layer->cm);
  }
  log = summary_lines(c.run, RunContext{m.label().toStdString(), "", 0});
  if (settings.target == TargetChoice::Atlas && written.wedge_texcoord) {
    log.push_back(
        "To see the atlas: Filters > Texture > Set Texture (MeshLab 2025.07: check Use dummy "
        "texture for a checkerboard; 2020.09 draws one where the named image does not exist); its "
        "seams: Filters > Texture > Select Vertex Texture Seams (the selection then holds the "
        "seams instead of the cones)");
  }
  return c;
}

}  // namespace ricci::plugin
