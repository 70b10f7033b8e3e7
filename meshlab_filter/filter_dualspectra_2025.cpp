#include "filter_dualspectra_2025.h"

#include "filter_text.h"
#include "localize_layers.h"
#include "option_parameters.h"

namespace {

/// The prefix of a filter's messages.
QString prefix(int filter)
{
    return filter == FilterDualSpectraPlugin::FP_RANK_LAYERS ? "Rank layers: " : "Localize partial shape: ";
}

[[noreturn]] void fail(int filter, const QString& message)
{
    throw MLException(prefix(filter) + message);
}

/// The layer a mesh parameter names, or a failure naming the parameter.
MeshModel* layer(int filter, MeshDocument& md, const RichParameterList& par, const QString& name)
{
    const unsigned int id = par.getMeshId(name);
    MeshModel* m = md.getMesh(id);
    if (m == nullptr) fail(filter, QString("%1: there is no layer with id %2").arg(name).arg(id));
    return m;
}

} // namespace

FilterDualSpectraPlugin::FilterDualSpectraPlugin()
{
    typeList = {FP_LOCALIZE_PARTIAL, FP_RANK_LAYERS};
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
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return dsml::filter_name();
    case FP_RANK_LAYERS: return dsml::search_filter_name();
    default: return QString();
    }
}

QString FilterDualSpectraPlugin::pythonFilterName(ActionIDType filterId) const
{
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return "dualspectra_localize";
    case FP_RANK_LAYERS: return "dualspectra_search";
    default: return QString();
    }
}

QString FilterDualSpectraPlugin::filterInfo(ActionIDType filterId) const
{
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return dsml::filter_info();
    case FP_RANK_LAYERS: return dsml::search_filter_info();
    default: return QString();
    }
}

FilterPlugin::FilterClass FilterDualSpectraPlugin::getClass(const QAction*) const
{
    return FilterPlugin::Selection;
}

FilterPlugin::FilterArity FilterDualSpectraPlugin::filterArity(const QAction* a) const
{
    // localize: the two layers are chosen by the full_mesh and partial_mesh parameters;
    // rank: every visible layer besides partial_mesh
    return ID(a) == FP_RANK_LAYERS ? VARIABLE : FIXED;
}

int FilterDualSpectraPlugin::getPreConditions(const QAction*) const
{
    return MeshModel::MM_NONE; // the chosen layers (not the current one) are checked in applyFilter
}

int FilterDualSpectraPlugin::postCondition(const QAction* a) const
{
    const int selection = MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT;
    return ID(a) == FP_RANK_LAYERS ? selection : selection | MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
}

RichParameterList FilterDualSpectraPlugin::initParameterList(const QAction* action, const MeshDocument& md)
{
    RichParameterList par;
    if (ID(action) == FP_RANK_LAYERS) {
        // Default: the current layer is the partial one.
        const MeshModel* partial = md.mm();
        par.addParam(RichMesh("partial_mesh", partial != nullptr ? partial->id() : 0, &md, dsml::partial_mesh_label(),
                              dsml::search_partial_mesh_tooltip()));
        dsml::add_option_parameters(par);
        return par;
    }
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
    switch (ID(action)) {
    case FP_LOCALIZE_PARTIAL: return localize(par, md, postConditionMask, cb);
    case FP_RANK_LAYERS: return rank(par, md, postConditionMask, cb);
    default: wrongActionCalled(action);
    }
    return {};
}

std::map<std::string, QVariant> FilterDualSpectraPlugin::localize(const RichParameterList& par, MeshDocument& md,
                                                                  unsigned int& postConditionMask,
                                                                  vcg::CallBackPos* cb)
{
    QString error;
    const dsml::OptionsPtr options = dsml::options_from_parameters(par, error);
    if (!options) fail(FP_LOCALIZE_PARTIAL, error);
    const bool writeScore = par.getBool("write_score");
    const dsml::LayersLocalized done = dsml::localize_layers(
        localizers, layer(FP_LOCALIZE_PARTIAL, md, par, "full_mesh"), layer(FP_LOCALIZE_PARTIAL, md, par, "partial_mesh"),
        options.get(), writeScore, cb, [this](bool warning, const QString& line) {
            log(warning ? GLLogStream::WARNING : GLLogStream::FILTER, qUtf8Printable(line));
        });
    if (!done.error.isEmpty()) fail(FP_LOCALIZE_PARTIAL, done.error);
    postConditionMask = MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT;
    if (writeScore) postConditionMask |= MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    return {
        {"selected_vertices", QVariant(int(done.selected_vertices))},
        {"selected_faces", QVariant(int(done.selected_faces))},
        {"confidence", QVariant(done.confidence)},
        {"cost", QVariant(done.cost)},
        {"optimisation_vertices", QVariant(int(done.optimisation_vertices))},
        {"seconds", QVariant(done.seconds)},
        {"reused", QVariant(done.reused)},
        {"warnings", QVariant(int(done.warnings))},
    };
}

std::map<std::string, QVariant> FilterDualSpectraPlugin::rank(const RichParameterList& par, MeshDocument& md,
                                                              unsigned int& postConditionMask, vcg::CallBackPos* cb)
{
    QString error;
    const dsml::OptionsPtr options = dsml::options_from_parameters(par, error);
    if (!options) fail(FP_RANK_LAYERS, error);
    std::vector<MeshModel*> layers;
    for (MeshModel& m : md.meshIterator()) layers.push_back(&m);
    const auto done = dsml::rank_layers(localizers, layers, layer(FP_RANK_LAYERS, md, par, "partial_mesh"),
                                        options.get(), cb, [this](bool warning, const QString& line) {
                                            log(warning ? GLLogStream::WARNING : GLLogStream::FILTER,
                                                qUtf8Printable(line));
                                        });
    if (!done.error.isEmpty()) fail(FP_RANK_LAYERS, done.error);
    postConditionMask = MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT;
    const auto& best = done.ranking.front();
    return {
        {"best_layer", QVariant(int(best.layer->id()))},
        {"score", QVariant(best.score)},
        {"confidence", QVariant(best.confidence)},
        {"selected_vertices", QVariant(int(done.selected_vertices))},
        {"selected_faces", QVariant(int(done.selected_faces))},
        {"ranked", QVariant(int(done.ranking.size()))},
        {"prepared", QVariant(int(done.prepared))},
        {"seconds", QVariant(done.seconds)},
    };
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
