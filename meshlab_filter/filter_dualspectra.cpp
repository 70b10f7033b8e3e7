#include "filter_dualspectra.h"

#include <limits>

#include "layer_arrays.h"
#include "localize_job.h"

namespace {

/// Names shown in the "Mode" drop-down, in the order of DS_MODE_DUAL, DS_MODE_LBO, DS_MODE_SI.
QStringList modeNames()
{
    return QStringList() << "dual (regular + scale-invariant)" << "lbo (Laplace-Beltrami only)"
                         << "si (scale-invariant only)";
}

ds_mode modeOfIndex(int i)
{
    switch (i) {
    case 1: return DS_MODE_LBO;
    case 2: return DS_MODE_SI;
    default: return DS_MODE_DUAL;
    }
}

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
    const ds_options def = ds_options_default();
    MeshModel* full = md.mm();
    // RichMesh asserts (active in Debian's build) that a non-null default is in the document.
    MeshDocument* doc = (full != nullptr && md.meshList.contains(full)) ? &md : nullptr;
    par.addParam(RichMesh("FullMesh", doc ? full : nullptr, doc, "Full mesh",
                          "The complete shape. The matched region is selected on this layer."));
    par.addParam(RichMesh("PartialMesh", doc ? otherLayer(md, full) : nullptr, doc, "Partial mesh",
                          "The part to localize: a triangle mesh, possibly a deformed copy of a part of the "
                          "full mesh. It must be a different layer with faces (not a point cloud)."));
    par.addParam(RichEnum("Mode", 0, modeNames(), "Mode",
                          "Which spectra are matched: dual = k regular + k scale-invariant eigenvalues (the "
                          "paper's method); lbo = 2k Laplace-Beltrami eigenvalues; si = 2k scale-invariant "
                          "eigenvalues."));
    par.addParam(RichInt("K", int(def.k), "Eigenvalues per spectrum (k)",
                         "Number of eigenvalues per spectrum. More is slower and more discriminative."));
    par.addParam(RichFloat("Alpha", float(def.alpha), "Scale-invariant exponent (alpha)",
                           "Exponent of the scale-invariant metric factor (eps + K^2)^(alpha/2), K the Gaussian "
                           "curvature."));
    par.addParam(RichInt("Seed", int(def.seed), "Random seed",
                         "Seed of every random choice: the same seed gives the same selection."));
    par.addParam(RichInt("SpectralCuts", int(def.spectral_cuts), "Spectral-cut starts",
                         "Further starts from the full mesh's first N eigenfunctions, two each: the region on "
                         "either side of a level set with the partial's area. For a part cut across a natural "
                         "axis (e.g. the left half of a body); 0 = none. Each adds ~15% to the time."));
    par.addParam(RichInt("PlaneCuts", int(def.plane_cuts), "Plane-cut starts",
                         "Further starts, one per direction: the side of a plane with the partial's area, normal "
                         "to the first N of 26 directions (6: both ways along the full mesh's principal axes; 14: "
                         "and the diagonals; 26: and the face diagonals). For a part cut off across the body; "
                         "0 = none. Each adds ~5% to the time."));
    par.addParam(RichBool("WriteScore", false, "Score to vertex quality and colour",
                          "Also write the per-vertex membership score in [0, 1] to the vertex quality of the "
                          "full mesh and colour it (red = in the region, blue = outside)."));
}

bool FilterDualSpectraPlugin::applyFilter(QAction* action, MeshDocument& /*md*/, const RichParameterList& par,
                                          vcg::CallBackPos* cb)
{
    if (ID(action) != FP_LOCALIZE_PARTIAL) return fail("unknown filter");
    const int k = par.getInt("K");
    const int seed = par.getInt("Seed");
    if (k < 1) return fail(QString("k must be at least 1 (got %1)").arg(k));
    if (seed < 0) return fail(QString("the seed must be non-negative (got %1)").arg(seed));
    const int cuts = par.getInt("SpectralCuts");
    if (cuts < 0) return fail(QString("the number of spectral cuts must be non-negative (got %1)").arg(cuts));
    const int planes = par.getInt("PlaneCuts");
    if (planes < 0) return fail(QString("the number of plane cuts must be non-negative (got %1)").arg(planes));
    ds_options options = ds_options_default();
    options.mode = modeOfIndex(par.getEnum("Mode"));
    options.k = size_t(k);
    options.alpha = double(par.getFloat("Alpha"));
    options.seed = uint64_t(seed);
    options.spectral_cuts = size_t(cuts);
    options.plane_cuts = size_t(planes);
    return localizePartial(par.getMesh("FullMesh"), par.getMesh("PartialMesh"), options, par.getBool("WriteScore"),
                           cb);
}

bool FilterDualSpectraPlugin::fail(const QString& message)
{
    errorMessage = "Localize partial shape: " + message;
    Log(GLLogStream::WARNING, qUtf8Printable(errorMessage));
    return false;
}

bool FilterDualSpectraPlugin::localizePartial(MeshModel* full, MeshModel* partial, const ds_options& options,
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
    if (fullArrays.n_unreferenced_vertices > 0)
        Log(GLLogStream::WARNING, "Localize partial shape: %zu vertices of '%s' belong to no face; they are ignored",
            fullArrays.n_unreferenced_vertices, qUtf8Printable(full->label()));

    const dsml::LocalizeOutcome out = dsml::run_localize(fullArrays, partialArrays, options, cb);
    if (out.status != DS_OK) {
        QString message = QString::fromStdString(out.error);
        const size_t skipped = fullArrays.n_deleted_vertices + fullArrays.n_unreferenced_vertices +
                               partialArrays.n_deleted_vertices + partialArrays.n_unreferenced_vertices;
        if (out.status == DS_INVALID_MESH && skipped > 0)
            message += "; vertex numbers count only the live vertices used by faces";
        return fail(message);
    }

    const size_t n = dsml::select_region(full->cm, fullArrays, out.region.data());
    full->cm.svn = int(n);
    full->cm.sfn = int(vcg::tri::UpdateSelection<CMeshO>::FaceCount(full->cm));
    if (writeScore) {
        full->updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
        dsml::write_quality(full->cm, fullArrays, out.score.data());
        vcg::tri::UpdateColor<CMeshO>::PerVertexQualityRamp(full->cm, Scalarm(1), Scalarm(0));
    }
    const char* modeName = options.mode == DS_MODE_LBO ? "lbo" : options.mode == DS_MODE_SI ? "si" : "dual";
    Log("Localized '%s' on '%s': %zu of %zu vertices selected (%.1f%%), %d faces; cost %.6g; %.2f s "
        "(mode %s, k %zu, alpha %.3g, seed %llu)",
        qUtf8Printable(partial->label()), qUtf8Printable(full->label()), n, fullArrays.n_vertices(),
        100.0 * double(n) / double(std::max<size_t>(1, fullArrays.n_vertices())), full->cm.sfn, out.cost, out.seconds,
        modeName, options.k, options.alpha, static_cast<unsigned long long>(options.seed));
    return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterDualSpectraPlugin)
