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
    typeList << FP_LOCALIZE_PARTIAL;
    for (FilterIDType tt : types())
        actionList << new QAction(filterName(tt), this);
}

QString FilterDualSpectraPlugin::pluginName() const
{
    return "FilterDualSpectra";
}

QString FilterDualSpectraPlugin::filterName(FilterIDType filterId) const
{
    return filterId == FP_LOCALIZE_PARTIAL ? dsml::filter_name() : QString();
}

QString FilterDualSpectraPlugin::filterInfo(FilterIDType filterId) const
{
    return filterId == FP_LOCALIZE_PARTIAL ? dsml::filter_info() : QString();
}

MeshFilterInterface::FilterClass FilterDualSpectraPlugin::getClass(QAction*)
{
    return MeshFilterInterface::Selection;
}

MeshFilterInterface::FILTER_ARITY FilterDualSpectraPlugin::filterArity(QAction*) const
{
    return FIXED; // the two layers are chosen by the "FullMesh" and "PartialMesh" parameters
}

int FilterDualSpectraPlugin::getPreConditions(QAction*) const
{
    return MeshModel::MM_NONE; // the chosen layers (not the current one) are checked in applyFilter
}

int FilterDualSpectraPlugin::postCondition(QAction*) const
{
    return MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_FACEFLAGSELECT | MeshModel::MM_VERTQUALITY |
           MeshModel::MM_VERTCOLOR;
}

void FilterDualSpectraPlugin::initParameterSet(QAction* action, MeshDocument& md, RichParameterList& par)
{
    if (ID(action) != FP_LOCALIZE_PARTIAL) return;
    MeshModel* full = md.mm();
    // RichMesh asserts (active in Debian's build) that a non-null default is in the document.
    MeshDocument* doc = (full != nullptr && md.meshList.contains(full)) ? &md : nullptr;
    par.addParam(RichMesh("FullMesh", doc ? full : nullptr, doc, dsml::full_mesh_label(), dsml::full_mesh_tooltip()));
    par.addParam(RichMesh("PartialMesh", doc ? otherLayer(md, full) : nullptr, doc, dsml::partial_mesh_label(),
                          dsml::partial_mesh_tooltip()));
    dsml::add_option_parameters(par);
    par.addParam(RichBool("WriteScore", false, dsml::write_score_label(), dsml::write_score_tooltip()));
}

bool FilterDualSpectraPlugin::applyFilter(QAction* action, MeshDocument& /*md*/, const RichParameterList& par,
                                          vcg::CallBackPos* cb)
{
    if (ID(action) != FP_LOCALIZE_PARTIAL) return fail("unknown filter");
    QString error;
    const dsml::OptionsPtr options = dsml::options_from_parameters(par, error);
    if (!options) return fail(error);
    const dsml::LayersLocalized done = dsml::localize_layers(
        localizers, par.getMesh("FullMesh"), par.getMesh("PartialMesh"), options.get(), par.getBool("WriteScore"), cb,
        [this](bool warning, const QString& line) {
            if (warning)
                Log(GLLogStream::WARNING, "%s", qUtf8Printable(line));
            else
                Log("%s", qUtf8Printable(line));
        });
    return done.error.isEmpty() || fail(done.error);
}

bool FilterDualSpectraPlugin::fail(const QString& message)
{
    errorMessage = "Localize partial shape: " + message;
    Log(GLLogStream::WARNING, "%s", qUtf8Printable(errorMessage));
    return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
