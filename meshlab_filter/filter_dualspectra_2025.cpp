#include "filter_dualspectra_2025.h"

#include "filter_text.h"
#include "localize_layers.h"
#include "option_parameters.h"

namespace {

[[noreturn]] void fail(const QString& message)
{
    throw MLException("Localize partial shape: " + message);
}

/// The layer a mesh parameter names, or a failure naming the parameter.
MeshModel* layer(MeshDocument& md, const RichParameterList& par, const QString& name)
{
    const unsigned int id = par.getMeshId(name);
    MeshModel* m = md.getMesh(id);
    if (m == nullptr) fail(QString("%1: there is no layer with id %2").arg(name).arg(id));
    return m;
}

} // namespace

FilterDualSpectraPlugin::FilterDualSpectraPlugin()
{
    typeList = {FP_LOCALIZE_PARTIAL};
    for (ActionIDType tt : types())
        actionList.push_back(new QAction(filterName(tt), this));
}

QString FilterDualSpectraPlugin::pluginName() const
{
    return "FilterDualSpectra";
}

QString FilterDualSpectraPlugin::vendor() const
{
    return "dualspectra";
}

QString FilterDualSpectraPlugin::filterName(ActionIDType filterId) const
{
    return filterId == FP_LOCALIZE_PARTIAL ? dsml::filter_name() : QString();
}

QString FilterDualSpectraPlugin::pythonFilterName(ActionIDType filterId) const
{
    return filterId == FP_LOCALIZE_PARTIAL ? QString("dualspectra_localize") : QString();
}

QString FilterDualSpectraPlugin::filterInfo(ActionIDType filterId) const
{
    return filterId == FP_LOCALIZE_PARTIAL ? dsml::filter_info() : QString();
}

FilterPlugin::FilterClass FilterDualSpectraPlugin::getClass(const QAction*) const
{
    return FilterPlugin::Selection;
}

FilterPlugin::FilterArity FilterDualSpectraPlugin::filterArity(const QAction*) const
{
    return FIXED; // the two layers are chosen by the full_mesh and partial_mesh parameters
}

int FilterDualSpectraPlugin::getPreConditions(const QAction*) const
{
    return MeshModel::MM_NONE; // the chosen layers (not the current one) are checked in applyFilter
}

int FilterDualSpectraPlugin::postCondition(const QAction*) const
{
    return MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT | MeshModel::MM_VERTQUALITY |
           MeshModel::MM_VERTCOLOR;
}

RichParameterList FilterDualSpectraPlugin::initParameterList(const QAction* action, const MeshDocument& md)
{
    RichParameterList par;
    if (ID(action) != FP_LOCALIZE_PARTIAL) return par;
    // Defaults: the current layer is the full mesh, the first other layer the partial one.
    const MeshModel* full = md.mm();
    const MeshModel* partial = full;
    for (const MeshModel& m : md.meshIterator()) {
        if (&m != full) {
            partial = &m;
            break;
        }
    }
    par.addParam(RichMesh("full_mesh", full != nullptr ? full->id() : 0, &md, dsml::full_mesh_label(),
                          dsml::full_mesh_tooltip()));
    par.addParam(RichMesh("partial_mesh", partial != nullptr ? partial->id() : 0, &md, dsml::partial_mesh_label(),
                          dsml::partial_mesh_tooltip()));
    dsml::add_option_parameters(par);
    par.addParam(RichBool("write_score", false, dsml::write_score_label(), dsml::write_score_tooltip()));
    return par;
}

std::map<std::string, QVariant> FilterDualSpectraPlugin::applyFilter(const QAction* action,
                                                                     const RichParameterList& par, MeshDocument& md,
                                                                     unsigned int& postConditionMask,
                                                                     vcg::CallBackPos* cb)
{
    if (ID(action) != FP_LOCALIZE_PARTIAL) wrongActionCalled(action);
    QString error;
    const dsml::OptionsPtr options = dsml::options_from_parameters(par, error);
    if (!options) fail(error);
    const bool writeScore = par.getBool("write_score");
    const dsml::LayersLocalized done = dsml::localize_layers(
        localizers, layer(md, par, "full_mesh"), layer(md, par, "partial_mesh"), options.get(), writeScore, cb,
        [this](bool warning, const QString& line) {
            log(warning ? GLLogStream::WARNING : GLLogStream::FILTER, qUtf8Printable(line));
        });
    if (!done.error.isEmpty()) fail(done.error);
    postConditionMask = MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT;
    if (writeScore) postConditionMask |= MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    return {
        {"selected_vertices", QVariant(int(done.selected_vertices))},
        {"selected_faces", QVariant(int(done.selected_faces))},
        {"confidence", QVariant(done.confidence)},
        {"cost", QVariant(done.cost)},
        {"seconds", QVariant(done.seconds)},
        {"reused", QVariant(done.reused)},
        {"warnings", QVariant(int(done.warnings))},
    };
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
