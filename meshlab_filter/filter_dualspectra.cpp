#include "filter_dualspectra.h"

#include "filter_text.h"
#include "localize_layers.h"
#include "option_parameters.h"

namespace {

/// The first layer of `md` other than `notThis` (or `notThis` when it is the only one).
MeshModel* otherLayer(MeshDocument& md, MeshModel* notThis)
{
    for (MeshModel* m : md.meshList)
        if (m != notThis) return m;
    return notThis;
}

} // namespace

FilterDualSpectraPlugin::FilterDualSpectraPlugin()
{
    typeList << FP_LOCALIZE_PARTIAL << FP_RANK_LAYERS;
    for (FilterIDType tt : types())
        actionList << new QAction(filterName(tt), this);
}

QString FilterDualSpectraPlugin::pluginName() const
{
    return "FilterDualSpectra";
}

QString FilterDualSpectraPlugin::filterName(FilterIDType filterId) const
{
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return dsml::filter_name();
    case FP_RANK_LAYERS: return dsml::search_filter_name();
    default: return QString();
    }
}

QString FilterDualSpectraPlugin::filterInfo(FilterIDType filterId) const
{
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return dsml::filter_info();
    case FP_RANK_LAYERS: return dsml::search_filter_info();
    default: return QString();
    }
}

MeshFilterInterface::FilterClass FilterDualSpectraPlugin::getClass(QAction*)
{
    return MeshFilterInterface::Selection;
}

MeshFilterInterface::FILTER_ARITY FilterDualSpectraPlugin::filterArity(QAction* a) const
{
    // localize: the two layers are chosen by the "FullMesh" and "PartialMesh" parameters;
    // rank: every visible layer besides "PartialMesh"
    return ID(a) == FP_RANK_LAYERS ? VARIABLE : FIXED;
}

int FilterDualSpectraPlugin::getPreConditions(QAction*) const
{
    return MeshModel::MM_NONE; // the chosen layers (not the current one) are checked in applyFilter
}

int FilterDualSpectraPlugin::postCondition(QAction* a) const
{
    const int selection = MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT;
    return ID(a) == FP_RANK_LAYERS ? selection : selection | MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
}

void FilterDualSpectraPlugin::initParameterSet(QAction* action, MeshDocument& md, RichParameterList& par)
{
    MeshModel* full = md.mm();
    // RichMesh asserts (active in Debian's build) that a non-null default is in the document.
    MeshDocument* doc = (full != nullptr && md.meshList.contains(full)) ? &md : nullptr;
    if (ID(action) == FP_RANK_LAYERS) {
        // Default: the current layer is the partial one.
        par.addParam(RichMesh("PartialMesh", doc ? full : nullptr, doc, dsml::partial_mesh_label(),
                              dsml::search_partial_mesh_tooltip()));
        dsml::add_option_parameters(par);
        return;
    }
    if (ID(action) != FP_LOCALIZE_PARTIAL) return;
    par.addParam(RichMesh("FullMesh", doc ? full : nullptr, doc, dsml::full_mesh_label(), dsml::full_mesh_tooltip()));
    par.addParam(RichMesh("PartialMesh", doc ? otherLayer(md, full) : nullptr, doc, dsml::partial_mesh_label(),
                          dsml::partial_mesh_tooltip()));
    dsml::add_option_parameters(par);
    par.addParam(RichBool("WriteScore", false, dsml::write_score_label(), dsml::write_score_tooltip()));
}

bool FilterDualSpectraPlugin::applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par,
                                          vcg::CallBackPos* cb)
{
    const int filter = ID(action);
    const QString prefix = filter == FP_RANK_LAYERS ? "Rank layers: " : "Localize partial shape: ";
    if (filter != FP_LOCALIZE_PARTIAL && filter != FP_RANK_LAYERS) return fail(prefix, "unknown filter");
    QString error;
    const dsml::OptionsPtr options = dsml::options_from_parameters(par, error);
    if (!options) return fail(prefix, error);
    auto log = [this](bool warning, const QString& line) { logLine(warning, line); };
    if (filter == FP_RANK_LAYERS) {
        const std::vector<MeshModel*> layers(md.meshList.begin(), md.meshList.end());
        const auto done = dsml::rank_layers(localizers, layers, par.getMesh("PartialMesh"), options.get(), cb, log);
        return done.error.isEmpty() || fail(prefix, done.error);
    }
    const dsml::LayersLocalized done = dsml::localize_layers(
        localizers, par.getMesh("FullMesh"), par.getMesh("PartialMesh"), options.get(), par.getBool("WriteScore"), cb,
        log);
    return done.error.isEmpty() || fail(prefix, done.error);
}

bool FilterDualSpectraPlugin::fail(const QString& prefix, const QString& message)
{
    errorMessage = prefix + message;
    Log(GLLogStream::WARNING, "%s", qUtf8Printable(errorMessage));
    return false;
}

void FilterDualSpectraPlugin::logLine(bool warning, const QString& line)
{
    if (warning)
        Log(GLLogStream::WARNING, "%s", qUtf8Printable(line));
    else
        Log("%s", qUtf8Printable(line));
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
