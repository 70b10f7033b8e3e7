// One localization between two MeshLab layers, and one ranking of layers for a partial layer,
// the same for both plugin interfaces: the layers are checked, packed (layer_arrays.h) and
// localized or ranked (localize_job.h); the region is written back as the (best) full layer's
// vertex and face selection and, on request, the score as vertex quality and colour. Every
// line for MeshLab's log goes through `log`. Templated on MeshLab's MeshModel, whose members
// used here (cm, label(), id(), isVisible(), updateDataMask, MM_*) are the same in MeshLab
// 2020.09 and 2025.07.
#ifndef DUALSPECTRA_MESHLAB_LOCALIZE_LAYERS_H
#define DUALSPECTRA_MESHLAB_LOCALIZE_LAYERS_H

#include <algorithm>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include <QString>

#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/algorithms/update/selection.h>

#include "layer_arrays.h"
#include "localize_job.h"

namespace dsml {

/// What `localize_layers` did. `error` is empty on success; otherwise nothing was changed and
/// it says why.
struct LayersLocalized {
    QString error;
    size_t selected_vertices = 0;
    size_t selected_faces = 0;
    size_t full_vertices = 0; ///< the full layer's live vertices
    double confidence = 0.0;  ///< in [0, 1]: estimated probability that IoU >= 0.5
    double cost = 0.0;
    double seconds = 0.0;     ///< locating the partial
    double scale = 1.0;       ///< the factor the partial was multiplied by (estimated with scale = auto)
    size_t optimisation_vertices = 0; ///< of the mesh the partial was optimised on
    bool reused = false;      ///< the full shape was prepared by an earlier call
    size_t warnings = 0;      ///< the library's notes, each logged as a warning
};

/// Locate the layer `partial` on the layer `full` with `options` (null layers, the same layer
/// twice or a layer without faces are refused here; the rest is the library's intake). The
/// region becomes `full`'s vertex selection, with the faces whose three vertices are in it;
/// with `write_score`, the score in [0, 1] is `full`'s vertex quality, coloured red (in) to
/// blue (out). `log(warning, line)` receives the preparation, each warning and the result;
/// `cb` the progress (false cancels).
template <class Model, class Log>
LayersLocalized localize_layers(LocalizerCache& cache, Model* full, Model* partial, const ds_options* options,
                                bool write_score, vcg::CallBackPos* cb, Log&& log)
{
    LayersLocalized done;
    if (full == nullptr || partial == nullptr) {
        done.error = "choose a full and a partial layer";
        return done;
    }
    if (full == partial) {
        done.error = QString("the full and the partial layer are the same layer ('%1'); choose two different layers")
                         .arg(full->label());
        return done;
    }
    for (Model* m : {partial, full}) {
        if (m->cm.fn == 0) {
            done.error = QString("the %1 layer '%2' has no faces (a point cloud?); it must be a triangle mesh")
                             .arg(m == full ? "full" : "partial", m->label());
            return done;
        }
    }

    const PackedLayer fullArrays = pack_layer(full->cm);
    const PackedLayer partialArrays = pack_layer(partial->cm);
    const LocalizeOutcome out = run_localize(cache, full->id(), fullArrays, partialArrays, options, cb);
    if (out.status != DS_OK) {
        done.error = QString::fromStdString(out.error);
        if (out.status == DS_INVALID_MESH && fullArrays.n_deleted_vertices + partialArrays.n_deleted_vertices > 0)
            done.error += "; vertex numbers count only the layer's live (not deleted) vertices";
        return done;
    }
    // (concatenated, not QString::arg'ed: a layer's label may hold a "%1")
    if (out.reused)
        log(false, "Localize partial shape: reused the full shape '" + full->label() +
                       "' prepared by an earlier call (same mesh and options)");
    else
        log(false, "Localize partial shape: prepared the full shape '" + full->label() + "' in " +
                       QString::number(out.preparation_seconds, 'f', 2) + " s (" +
                       QString::number(out.optimisation_vertices) +
                       " optimisation vertices); kept for further parts on this layer");
    for (const std::string& w : out.warnings)
        log(true, "Localize partial shape: " + QString::fromStdString(w));

    using Mesh = typename std::remove_reference<decltype(full->cm)>::type;
    done.selected_vertices = select_region(full->cm, fullArrays, out.region.data());
    done.selected_faces = vcg::tri::UpdateSelection<Mesh>::FaceCount(full->cm);
    full->cm.svn = int(done.selected_vertices);
    full->cm.sfn = int(done.selected_faces);
    if (write_score) {
        full->updateDataMask(Model::MM_VERTQUALITY | Model::MM_VERTCOLOR);
        write_quality(full->cm, fullArrays, out.score.data());
        using Scalar = typename Mesh::ScalarType;
        vcg::tri::UpdateColor<Mesh>::PerVertexQualityRamp(full->cm, Scalar(1), Scalar(0));
    }
    done.full_vertices = fullArrays.n_vertices();
    done.confidence = out.confidence;
    done.cost = out.cost;
    done.seconds = out.seconds;
    done.scale = out.scale;
    done.optimisation_vertices = out.optimised_on_vertices;
    done.reused = out.reused;
    done.warnings = out.warnings.size();
    const char* json = ds_options_json(options);
    const double percent = 100.0 * double(done.selected_vertices) / double(std::max<size_t>(1, done.full_vertices));
    log(false, "Localized '" + partial->label() + "' on '" + full->label() + "': " +
                   QString::number(done.selected_vertices) + " of " + QString::number(done.full_vertices) +
                   " vertices selected (" + QString::number(percent, 'f', 1) + "%), " +
                   QString::number(done.selected_faces) + " faces; confidence " +
                   QString::number(done.confidence, 'f', 2) + "; cost " + QString::number(done.cost, 'g', 6) +
                   "; optimised on " + QString::number(done.optimisation_vertices) + " vertices; " +
                   (done.scale != 1.0 ? "partial scaled by " + QString::number(done.scale, 'g', 4) + "; " : QString()) +
                   QString::number(done.seconds, 'f', 2) + " s; options " +
                   QString::fromUtf8(json != nullptr ? json : ""));
    return done;
}

/// What `rank_layers` did. `error` is empty on success; otherwise nothing was changed and it
/// says why.
template <class Model>
struct LayersRanked {
    QString error;
    struct Row {
        Model* layer = nullptr;
        double score = 0.0;      ///< lower is more similar; +inf when not located
        double confidence = 0.0; ///< in [0, 1]: estimated probability that IoU >= 0.5
        QString error;           ///< why the partial could not be located on the layer
    };
    std::vector<Row> ranking;    ///< the layers ranked, best first
    size_t selected_vertices = 0;
    size_t selected_faces = 0;
    size_t prepared = 0;         ///< layers prepared by this call (the others were kept)
    double seconds = 0.0;
};

/// Rank every visible mesh layer of `layers` other than `partial` by how similar `partial` is
/// to a part of it (the library's search: lower score is more similar) with `options`, and
/// select the region on the best one, as `localize_layers` does (the other layers are not
/// changed). Layers without faces are skipped (logged). `log(warning, line)` receives the
/// preparations, the ranking (one line per layer: rank, name, score, confidence) and the best
/// result's warnings; `cb` the progress.
template <class Model, class Log>
LayersRanked<Model> rank_layers(LocalizerCache& cache, const std::vector<Model*>& layers, Model* partial,
                                const ds_options* options, vcg::CallBackPos* cb, Log&& log)
{
    LayersRanked<Model> done;
    if (partial == nullptr) {
        done.error = "choose a partial layer";
        return done;
    }
    if (partial->cm.fn == 0) {
        done.error = "the partial layer '" + partial->label() + "' has no faces (a point cloud?); it must be a triangle mesh";
        return done;
    }
    std::vector<Model*> fulls;
    for (Model* m : layers) {
        if (m == nullptr || m == partial || !m->isVisible()) continue;
        if (m->cm.fn == 0)
            log(true, "Rank layers: skipped the layer '" + m->label() + "': it has no faces");
        else
            fulls.push_back(m);
    }
    if (fulls.empty()) {
        done.error = "no visible mesh layer besides the partial layer '" + partial->label() +
                     "': load the models as layers and show them";
        return done;
    }

    std::vector<PackedLayer> arrays;
    arrays.reserve(fulls.size());
    std::vector<SearchLayer> searched;
    for (Model* m : fulls) {
        arrays.push_back(pack_layer(m->cm));
        searched.push_back(SearchLayer{m->id(), m->label().toStdString(), &arrays.back()});
    }
    const PackedLayer partialArrays = pack_layer(partial->cm);
    const SearchOutcome out = run_search(cache, searched, partialArrays, options, cb);
    if (out.status != DS_OK) {
        done.error = QString::fromStdString(out.error);
        return done;
    }
    const size_t kept = fulls.size() - out.prepared;
    log(false, "Rank layers: prepared " + QString::number(out.prepared) + " layer(s) in " +
                   QString::number(out.preparation_seconds, 'f', 2) + " s, reused " + QString::number(kept) +
                   " prepared by an earlier call");
    for (const RankedLayer& r : out.ranking) {
        typename LayersRanked<Model>::Row row;
        row.layer = fulls[r.layer];
        row.score = r.score;
        row.confidence = r.confidence;
        row.error = QString::fromStdString(r.error);
        done.ranking.push_back(row);
        // (concatenated, not QString::arg'ed: a layer's label may hold a "%1")
        const QString rank = "Rank " + QString::number(done.ranking.size()) + ": '" + row.layer->label() + "' ";
        if (row.error.isEmpty())
            log(false, rank + "score " + QString::number(row.score, 'g', 4) + ", confidence " +
                           QString::number(row.confidence, 'f', 2));
        else
            log(false, rank + "not located: " + row.error);
    }
    for (const std::string& w : out.warnings) log(true, "Rank layers: " + QString::fromStdString(w));

    Model* best = done.ranking.front().layer;
    using Mesh = typename std::remove_reference<decltype(best->cm)>::type;
    done.selected_vertices = select_region(best->cm, arrays[out.ranking.front().layer], out.region.data());
    done.selected_faces = vcg::tri::UpdateSelection<Mesh>::FaceCount(best->cm);
    best->cm.svn = int(done.selected_vertices);
    best->cm.sfn = int(done.selected_faces);
    done.prepared = out.prepared;
    done.seconds = out.seconds;
    const char* json = ds_options_json(options);
    log(false, "Ranked " + QString::number(fulls.size()) + " layer(s) for '" + partial->label() + "': best '" +
                   best->label() + "' (score " + QString::number(done.ranking.front().score, 'g', 4) +
                   ", confidence " + QString::number(done.ranking.front().confidence, 'f', 2) + "), " +
                   QString::number(done.selected_vertices) + " vertices and " + QString::number(done.selected_faces) +
                   " faces selected on it; " + QString::number(done.seconds, 'f', 2) + " s; options " +
                   QString::fromUtf8(json != nullptr ? json : ""));
    return done;
}

} // namespace dsml

#endif
