// The dualspectra C ABI calls of one localization for two packed layers, and of one ranking
// of several full layers for a partial one, with MeshLab's progress callback
// (`vcg::CallBackPos`) driven from the caller's thread, and the prepared full shapes
// (`ds_localizer`) kept between calls. No MeshLab plugin interface types here: this file is
// the same for MeshLab 2020.09 and 2022+.
#ifndef DUALSPECTRA_MESHLAB_LOCALIZE_JOB_H
#define DUALSPECTRA_MESHLAB_LOCALIZE_JOB_H

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <dualspectra/dualspectra.h>
#include <cstring> // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "layer_arrays.h"

namespace dsml {

/// The prepared full shapes, one per full layer, each kept while the layer's geometry and the
/// options are those it was prepared for (its key: vertex and face counts, a hash of the
/// coordinates and faces, and the options' JSON), so that locating several parts on one model,
/// or ranking a library of layers again, prepares each once. At most `capacity` layers are
/// kept (the least recently used goes).
class LocalizerCache {
public:
    explicit LocalizerCache(size_t capacity = 16) : capacity_(capacity) {}

    using Localizer = std::shared_ptr<ds_localizer>;

    /// The localizer of `layer` if it was prepared for `key`, else null.
    Localizer find(int layer, const std::string& key);
    /// Keep `localizer` as the one of `layer`, prepared for `key`.
    void keep(int layer, const std::string& key, Localizer localizer);
    /// Forget every prepared shape.
    void clear();

private:
    struct Entry {
        std::string key;
        Localizer localizer;
        uint64_t last_use = 0;
    };
    std::mutex mutex_;
    std::map<int, Entry> entries_;
    uint64_t clock_ = 0;
    size_t capacity_;
};

/// What `run_localize` returns. `status == DS_OK` on success; otherwise `error` says why
/// (prefixed with the layer it concerns when the mesh itself was rejected).
struct LocalizeOutcome {
    ds_status status = DS_OK;
    std::string error;
    std::vector<uint8_t> region; ///< per packed vertex of the full layer: 1 = in the region
    std::vector<double> score;   ///< per packed vertex of the full layer, in [0, 1]
    double cost = 0.0;
    double confidence = 0.0;          ///< in [0, 1]: estimated probability that IoU >= 0.5
    double seconds = 0.0;             ///< locating the partial
    double scale = 1.0;               ///< the factor the partial was multiplied by (the estimate with scale = auto)
    double preparation_seconds = 0.0; ///< preparing the full shape (when it was prepared now)
    bool reused = false;              ///< the full shape was prepared by an earlier call
    size_t optimisation_vertices = 0; ///< of the prepared full shape's optimisation mesh
    size_t optimised_on_vertices = 0; ///< of the mesh this result was optimised on (finer for a partial with holes)
    std::vector<std::string> warnings; ///< the library's notes (left-out vertices, repairs, ...)
};

/// Locate `partial` on `full` (the layer with id `full_layer`) with `options`, on a worker
/// thread, while the calling thread forwards the progress to `cb` every 100 ms as a
/// percentage; `cb` returning false cancels (`DS_CANCELLED`). `cb` may be null. The full shape
/// is prepared unless `cache` holds it for the same geometry and options. Never throws: every
/// failure is reported in the outcome.
LocalizeOutcome run_localize(LocalizerCache& cache, int full_layer, const PackedLayer& full, const PackedLayer& partial,
                             const ds_options* options, vcg::CallBackPos* cb);

/// A full layer to rank: its id (the cache's key), its name (for messages) and its arrays.
struct SearchLayer {
    int id = 0;
    std::string name;
    const PackedLayer* arrays = nullptr;
};

/// One ranked layer of `run_search`.
struct RankedLayer {
    size_t layer = 0;         ///< position in the layers given
    double score = 0.0;       ///< similarity score, lower is more similar; +inf when not located
    double confidence = 0.0;  ///< that the partial is a part of this layer rather than of another one ranked, in [0, 1] (0 when not located)
    std::string error;        ///< why the partial could not be located on it ("" if it was)
};

/// What `run_search` returns. `status == DS_OK` on success; otherwise `error` says why.
struct SearchOutcome {
    ds_status status = DS_OK;
    std::string error;
    std::vector<RankedLayer> ranking;  ///< every layer given, best first
    std::vector<uint8_t> region;       ///< per packed vertex of the best layer: 1 = in the region
    std::vector<std::string> warnings; ///< the library's notes on the best layer's result
    size_t prepared = 0;               ///< layers prepared by this call (the others were kept)
    double preparation_seconds = 0.0;  ///< preparing them
    double seconds = 0.0;              ///< the whole call
};

/// Rank `fulls` for `partial` with `options` (`ds_search`), on a worker thread, with the
/// progress forwarded to `cb` as `run_localize` does. Each full layer is prepared unless
/// `cache` holds it for the same geometry and options (then kept there). Never throws.
SearchOutcome run_search(LocalizerCache& cache, const std::vector<SearchLayer>& fulls, const PackedLayer& partial,
                         const ds_options* options, vcg::CallBackPos* cb);

} // namespace dsml

#endif
