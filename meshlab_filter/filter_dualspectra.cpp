#include "filter_dualspectra.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

#include <climits>
#include <limits>
#include <memory>
#include <vector>

#include "layer_arrays.h"

namespace {

/// One option of the library's table (ds_options_schema_json): a filter parameter of the same
/// name.
struct OptionParam {
    QString name, label, doc, type; ///< type: "int", "float" or "choice"
    QJsonValue defaultValue, min, max;
    QStringList choices;
};

/// The library's options, parsed once (empty only if the library's JSON were unreadable).
const std::vector<OptionParam>& optionParams()
{
    static const std::vector<OptionParam> params = [] {
        std::vector<OptionParam> out;
        const QJsonArray list = QJsonDocument::fromJson(QByteArray(ds_options_schema_json())).array();
        for (const QJsonValue& entry : list) {
            const QJsonObject o = entry.toObject();
            OptionParam p;
            p.name = o.value("name").toString();
            p.label = o.value("label").toString();
            p.doc = o.value("doc").toString();
            p.type = o.value("type").toString();
            p.defaultValue = o.value("default");
            p.min = o.value("min");
            p.max = o.value("max");
            for (const QJsonValue& c : o.value("choices").toArray()) p.choices << c.toString();
            out.push_back(p);
        }
        return out;
    }();
    return params;
}

/// The tooltip: the library's doc and the range.
QString tooltip(const OptionParam& p)
{
    if (p.type == "choice") return p.doc + " One of: " + p.choices.join(", ") + ".";
    const QString max = p.max.toDouble() >= double(INT_MAX) && p.type == "int" ? QString::number(INT_MAX)
                                                                                 : QString::number(p.max.toDouble());
    return p.doc + QString(" Range: %1 to %2.").arg(QString::number(p.min.toDouble()), max);
}

/// The parameter of `p` with the library's default.
RichParameter* richParameter(const OptionParam& p)
{
    if (p.type == "int") {
        const double def = std::min(p.defaultValue.toDouble(), double(INT_MAX));
        return new RichInt(p.name, int(def), p.label, tooltip(p));
    }
    if (p.type == "float") return new RichFloat(p.name, float(p.defaultValue.toDouble()), p.label, tooltip(p));
    const int index = std::max(0, p.choices.indexOf(p.defaultValue.toString()));
    return new RichEnum(p.name, index, p.choices, p.label, tooltip(p));
}

/// The value of `p` in `par` as the text the library parses; empty with `error` set if a
/// choice index is out of range.
QString parameterText(const OptionParam& p, const RichParameterList& par, QString& error)
{
    if (p.type == "int") return QString::number(par.getInt(p.name));
    if (p.type == "float") return QString::number(double(par.getFloat(p.name)), 'g', 7);
    const int i = par.getEnum(p.name);
    if (i < 0 || i >= p.choices.size()) {
        error = QString("%1: choice %2 is out of range (%3 choices: %4)")
                    .arg(p.name)
                    .arg(i)
                    .arg(p.choices.size())
                    .arg(p.choices.join(", "));
        return QString();
    }
    return p.choices[i];
}

struct OptionsDeleter {
    void operator()(ds_options* o) const { ds_options_destroy(o); }
};

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
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL: return "Localize partial shape (dual spectra)";
    default: return QString();
    }
}

QString FilterDualSpectraPlugin::filterInfo(FilterIDType filterId) const
{
    switch (filterId) {
    case FP_LOCALIZE_PARTIAL:
        return "Selects the region of the <b>full</b> layer that the <b>partial</b> layer is, even when the "
               "partial shape is a deformed (near-isometric) copy of a part of the full one. "
               "The vertices of the region and the faces whose three vertices are in it are selected; "
               "optionally a soft membership score in [0, 1] is written to vertex quality and colour "
               "(red = in the region).<br>"
               "The region is found by optimising a potential on the full shape so that the spectra of its "
               "Hamiltonian match the Dirichlet spectra of the partial shape, in the regular and in a "
               "scale-invariant metric.<br>"
               "<i>A. Bracha, T. Dag&egrave;s, R. Kimmel</i><br>"
               "<b>\"Partial Shape Similarity by Multi-metric Hamiltonian Spectra Matching\"</b><br>"
               "SSVM 2023. Implementation: dualspectra " +
               QString(ds_version()) + ".";
    default: return QString();
    }
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
    par.addParam(RichMesh("FullMesh", doc ? full : nullptr, doc, "Full mesh",
                          "The complete shape. The matched region is selected on this layer."));
    par.addParam(RichMesh("PartialMesh", doc ? otherLayer(md, full) : nullptr, doc, "Partial mesh",
                          "The part to localize: a triangle mesh, possibly a deformed copy of a part of the "
                          "full mesh. It must be a different layer with faces (not a point cloud)."));
    // The localizer's options, as the library lists them (names, labels, defaults, docs).
    for (const OptionParam& p : optionParams()) {
        std::unique_ptr<RichParameter> rp(richParameter(p));
        par.addParam(*rp);
    }
    par.addParam(RichBool("WriteScore", false, "Score to vertex quality and colour",
                          "Also write the per-vertex membership score in [0, 1] to the vertex quality of the "
                          "full mesh and colour it (red = in the region, blue = outside)."));
}

bool FilterDualSpectraPlugin::applyFilter(QAction* action, MeshDocument& /*md*/, const RichParameterList& par,
                                          vcg::CallBackPos* cb)
{
    if (ID(action) != FP_LOCALIZE_PARTIAL) return fail("unknown filter");
    if (optionParams().empty()) return fail("the library's option table could not be read");
    ds_options* raw = nullptr;
    if (ds_options_create(&raw) != DS_OK) return fail(QString("options: ") + ds_last_error_message());
    std::unique_ptr<ds_options, OptionsDeleter> options(raw);
    // Each value goes to the library by name, as text; the library checks it and names the
    // option and its range when it refuses it.
    for (const OptionParam& p : optionParams()) {
        QString error;
        const QString text = parameterText(p, par, error);
        if (!error.isEmpty()) return fail(error);
        if (ds_options_set(options.get(), qUtf8Printable(p.name), qUtf8Printable(text)) != DS_OK)
            return fail(QString::fromUtf8(ds_last_error_message()));
    }
    return localizePartial(par.getMesh("FullMesh"), par.getMesh("PartialMesh"), options.get(),
                           par.getBool("WriteScore"), cb);
}

bool FilterDualSpectraPlugin::fail(const QString& message)
{
    errorMessage = "Localize partial shape: " + message;
    Log(GLLogStream::WARNING, qUtf8Printable(errorMessage));
    return false;
}

bool FilterDualSpectraPlugin::localizePartial(MeshModel* full, MeshModel* partial, const ds_options* options,
                                              bool writeScore, vcg::CallBackPos* cb)
{
    if (full == nullptr || partial == nullptr) return fail("choose a full and a partial layer");
    if (full == partial)
        return fail(QString("the full and the partial layer are the same layer ('%1'); choose two different "
                            "layers")
                        .arg(full->label()));
    if (partial->cm.fn == 0)
        return fail(QString("the partial layer '%1' has no faces (a point cloud?); it must be a triangle mesh")
                        .arg(partial->label()));
    if (full->cm.fn == 0)
        return fail(QString("the full layer '%1' has no faces (a point cloud?); it must be a triangle mesh")
                        .arg(full->label()));

    const dsml::PackedLayer fullArrays = dsml::pack_layer(full->cm);
    const dsml::PackedLayer partialArrays = dsml::pack_layer(partial->cm);
    const dsml::LocalizeOutcome out =
        dsml::run_localize(localizers, full->id(), fullArrays, partialArrays, options, cb);
    if (out.status != DS_OK) {
        QString message = QString::fromStdString(out.error);
        if (out.status == DS_INVALID_MESH && fullArrays.n_deleted_vertices + partialArrays.n_deleted_vertices > 0)
            message += "; vertex numbers count only the layer's live (not deleted) vertices";
        return fail(message);
    }
    if (out.reused)
        Log("Localize partial shape: reused the full shape '%s' prepared by an earlier call (same mesh and options)",
            qUtf8Printable(full->label()));
    else
        Log("Localize partial shape: prepared the full shape '%s' in %.2f s (%zu optimisation vertices); kept for "
            "further parts on this layer",
            qUtf8Printable(full->label()), out.preparation_seconds, out.optimisation_vertices);
    for (const std::string& w : out.warnings) Log(GLLogStream::WARNING, "Localize partial shape: %s", w.c_str());

    const size_t n = dsml::select_region(full->cm, fullArrays, out.region.data());
    full->cm.svn = int(n);
    full->cm.sfn = int(vcg::tri::UpdateSelection<CMeshO>::FaceCount(full->cm));
    if (writeScore) {
        full->updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
        dsml::write_quality(full->cm, fullArrays, out.score.data());
        vcg::tri::UpdateColor<CMeshO>::PerVertexQualityRamp(full->cm, Scalarm(1), Scalarm(0));
    }
    const char* json = ds_options_json(options);
    Log("Localized '%s' on '%s': %zu of %zu vertices selected (%.1f%%), %d faces; confidence %.2f; cost %.6g; %.2f s; "
        "options %s",
        qUtf8Printable(partial->label()), qUtf8Printable(full->label()), n, fullArrays.n_vertices(),
        100.0 * double(n) / double(std::max<size_t>(1, fullArrays.n_vertices())), full->cm.sfn, out.confidence, out.cost,
        out.seconds, json != nullptr ? json : "");
    return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
