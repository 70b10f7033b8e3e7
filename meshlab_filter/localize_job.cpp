#include "localize_job.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <functional>
#include <thread>

namespace dsml {

// ---------------------------------------------------------------------------------------------
// LocalizerCache

LocalizerCache::Localizer LocalizerCache::find(int layer, const std::string& key)
{
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = entries_.find(layer);
    if (it == entries_.end() || it->second.key != key) return nullptr;
    it->second.last_use = ++clock_;
    return it->second.localizer;
}

void LocalizerCache::keep(int layer, const std::string& key, Localizer localizer)
{
    std::lock_guard<std::mutex> lock(mutex_);
    entries_[layer] = Entry{key, std::move(localizer), ++clock_};
    while (entries_.size() > capacity_) {
        auto oldest = std::min_element(entries_.begin(), entries_.end(), [](const auto& a, const auto& b) {
            return a.second.last_use < b.second.last_use;
        });
        entries_.erase(oldest);
    }
}

void LocalizerCache::clear()
{
    std::lock_guard<std::mutex> lock(mutex_);
    entries_.clear();
}

namespace {

struct MeshDeleter {
    void operator()(ds_mesh* m) const { ds_mesh_destroy(m); }
};
struct ResultDeleter {
    void operator()(ds_result* r) const { ds_result_destroy(r); }
};
using MeshPtr = std::unique_ptr<ds_mesh, MeshDeleter>;
using ResultPtr = std::unique_ptr<ds_result, ResultDeleter>;

/// State shared by the worker (writer of progress) and the caller (reader, canceller).
struct Shared {
    std::mutex mutex;
    std::condition_variable done_cv;
    bool done = false;
    double fraction = 0.0;
    std::string stage = "starting";
    /// The part of the whole job the current library call reports into.
    double lo = 0.0, hi = 1.0;
    std::string phase;
    std::atomic<bool> cancel{false};

    void enter(double a, double b, const char* name)
    {
        std::lock_guard<std::mutex> lock(mutex);
        lo = a;
        hi = b;
        phase = name;
    }
};

/// `ds_progress_fn`: record the progress for the caller's thread; 0 asks the library to stop.
/// Runs on a library thread, so it never touches MeshLab (and never throws).
int record_progress(double fraction, const char* stage, void* user)
{
    auto* s = static_cast<Shared*>(user);
    try {
        std::lock_guard<std::mutex> lock(s->mutex);
        s->fraction = s->lo + (s->hi - s->lo) * fraction;
        if (stage != nullptr) s->stage = s->phase + stage;
    } catch (...) {
        // keep the previous stage text on allocation failure
    }
    return s->cancel.load() ? 0 : 1;
}

/// The message of the last failed call on this thread, with the status name.
std::string describe(ds_status status, const char* what)
{
    std::string msg = what;
    msg += ": ";
    const char* detail = ds_last_error_message();
    msg += (detail != nullptr && *detail != '\0') ? detail : "no detail";
    msg += " (";
    msg += ds_status_name(status);
    msg += ")";
    return msg;
}

/// A host mesh handle of a packed layer.
ds_status make_mesh(const PackedLayer& p, MeshPtr& out)
{
    ds_mesh* raw = nullptr;
    const ds_status st = ds_mesh_create_from_host(p.xyz.data(), p.n_vertices(), p.tri.data(), p.n_faces(), &raw);
    out.reset(raw);
    return st;
}

/// The key a prepared full shape is kept under.
std::string cache_key(const PackedLayer& full, const ds_options* options)
{
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fingerprint(full)));
    const char* json = ds_options_json(options);
    return std::to_string(full.n_vertices()) + " " + std::to_string(full.n_faces()) + " " + hash + " " +
           (json != nullptr ? json : "");
}

/// A full layer's prepared shape for one call.
struct PreparedLayer {
    LocalizerCache::Localizer localizer;
    bool reused = false;
    double preparation_seconds = 0.0;
};

/// The prepared shape of the layer `layer` (arrays `full`): the cache's, or prepared now with
/// its progress in [lo, hi] of the job (stage prefix `phase`) and kept. On failure, the status,
/// and `error` says why, naming the layer as `what` ("full layer", "layer 'x'").
ds_status prepare_layer(LocalizerCache& cache, int layer, const PackedLayer& full, const std::string& what,
                        const ds_options* options, Shared& shared, double lo, double hi, const std::string& phase,
                        PreparedLayer& out, std::string& error)
{
    const std::string key = cache_key(full, options);
    out.localizer = cache.find(layer, key);
    out.reused = out.localizer != nullptr;
    if (out.reused) return DS_OK;
    MeshPtr full_mesh;
    ds_status st = make_mesh(full, full_mesh);
    if (st != DS_OK) { error = describe(st, (what + " rejected").c_str()); return st; }
    shared.enter(lo, hi, phase.c_str());
    ds_localizer* raw = nullptr;
    st = ds_localizer_create(full_mesh.get(), options, &record_progress, &shared, &raw);
    out.localizer = LocalizerCache::Localizer(raw, ds_localizer_destroy);
    if (st != DS_OK) { error = describe(st, ("preparing the " + what + " failed").c_str()); return st; }
    cache.keep(layer, key, out.localizer);
    ds_localizer_preparation_seconds(out.localizer.get(), &out.preparation_seconds);
    return DS_OK;
}

/// The library's notes on a result.
std::vector<std::string> warnings_of(const ds_result* result)
{
    std::vector<std::string> out;
    for (size_t i = 0; i < ds_result_n_warnings(result); ++i) out.emplace_back(ds_result_warning(result, i));
    return out;
}

/// The whole C-ABI sequence; runs on the worker thread, so that `ds_last_error_message`
/// (per thread) is read on the thread that failed. The partial is checked first (cheap), then
/// the full shape is prepared if it must be, then the partial located.
void localize_on_worker(LocalizerCache& cache, int full_layer, const PackedLayer& full, const PackedLayer& partial,
                        const ds_options* options, Shared& shared, LocalizeOutcome& out)
{
    MeshPtr partial_mesh;
    ds_status st = make_mesh(partial, partial_mesh);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "partial layer rejected"); return; }

    PreparedLayer prepared;
    st = prepare_layer(cache, full_layer, full, "full layer", options, shared, 0.0, 0.3, "preparing the full shape: ",
                       prepared, out.error);
    if (st != DS_OK) { out.status = st; return; }
    out.reused = prepared.reused;
    out.preparation_seconds = prepared.preparation_seconds;
    out.optimisation_vertices = ds_localizer_optimisation_vertices(prepared.localizer.get());

    shared.enter(out.reused ? 0.0 : 0.3, 1.0, "");
    ds_result* raw_result = nullptr;
    st = ds_localizer_locate(prepared.localizer.get(), partial_mesh.get(), &record_progress, &shared, &raw_result);
    ResultPtr result(raw_result);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "localization failed"); return; }

    const size_t n = ds_result_n_vertices(result.get());
    if (n != full.n_vertices()) {
        out.status = DS_PANIC;
        out.error = "the result has " + std::to_string(n) + " vertices, the full layer " +
                    std::to_string(full.n_vertices());
        return;
    }
    out.region.resize(n);
    out.score.resize(n);
    if ((st = ds_result_region(result.get(), out.region.data(), n)) != DS_OK ||
        (st = ds_result_score(result.get(), out.score.data(), n)) != DS_OK ||
        (st = ds_result_cost(result.get(), &out.cost)) != DS_OK ||
        (st = ds_result_confidence(result.get(), &out.confidence)) != DS_OK ||
        (st = ds_result_optimisation_vertices(result.get(), &out.optimised_on_vertices)) != DS_OK ||
        (st = ds_result_seconds(result.get(), &out.seconds)) != DS_OK ||
        (st = ds_result_scale(result.get(), &out.scale)) != DS_OK) {
        out.status = st;
        out.error = describe(st, "reading the result failed");
        return;
    }
    out.warnings = warnings_of(result.get());
}

struct SearchDeleter {
    void operator()(ds_search_result* s) const { ds_search_result_destroy(s); }
};
using SearchPtr = std::unique_ptr<ds_search_result, SearchDeleter>;

/// The C-ABI sequence of a ranking, on the worker thread: the partial is checked, every full
/// layer prepared unless kept (the first half of the progress, shared evenly among those to
/// prepare), then `ds_search` ranks them all (the rest).
void search_on_worker(LocalizerCache& cache, const std::vector<SearchLayer>& fulls, const PackedLayer& partial,
                      const ds_options* options, Shared& shared, SearchOutcome& out)
{
    MeshPtr partial_mesh;
    ds_status st = make_mesh(partial, partial_mesh);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "partial layer rejected"); return; }

    size_t to_prepare = 0;
    for (const SearchLayer& f : fulls)
        if (!cache.find(f.id, cache_key(*f.arrays, options))) ++to_prepare;
    const double prepare_part = to_prepare > 0 ? 0.5 : 0.0;
    std::vector<PreparedLayer> prepared(fulls.size());
    std::vector<const ds_localizer*> localizers;
    for (size_t i = 0; i < fulls.size(); ++i) {
        const double lo = prepare_part * double(out.prepared) / double(std::max<size_t>(1, to_prepare));
        const double hi = prepare_part * double(out.prepared + 1) / double(std::max<size_t>(1, to_prepare));
        const std::string what = "layer '" + fulls[i].name + "'";
        st = prepare_layer(cache, fulls[i].id, *fulls[i].arrays, what, options, shared, lo, hi,
                           "preparing " + what + ": ", prepared[i], out.error);
        if (st != DS_OK) { out.status = st; return; }
        if (!prepared[i].reused) {
            ++out.prepared;
            out.preparation_seconds += prepared[i].preparation_seconds;
        }
        localizers.push_back(prepared[i].localizer.get());
    }

    shared.enter(prepare_part, 1.0, "ranking: ");
    ds_search_result* raw = nullptr;
    st = ds_search(localizers.data(), localizers.size(), partial_mesh.get(), localizers.size(), &record_progress,
                   &shared, &raw);
    SearchPtr ranked(raw);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "ranking failed"); return; }

    for (size_t rank = 0; rank < ds_search_result_count(ranked.get()); ++rank) {
        RankedLayer row;
        const ds_result* result = ds_search_result_result(ranked.get(), rank);
        if ((st = ds_search_result_index(ranked.get(), rank, &row.layer)) != DS_OK ||
            (st = ds_search_result_score(ranked.get(), rank, &row.score)) != DS_OK ||
            (result != nullptr && (st = ds_search_result_confidence(ranked.get(), rank, &row.confidence)) != DS_OK)) {
            out.status = st;
            out.error = describe(st, "reading the ranking failed");
            return;
        }
        if (const char* why = ds_search_result_error(ranked.get(), rank)) row.error = why;
        out.ranking.push_back(row);
    }
    // The best layer's region (ds_search fails when no layer can take the partial, so the
    // best is located).
    const ds_result* best = ds_search_result_result(ranked.get(), 0);
    const size_t n = best != nullptr ? ds_result_n_vertices(best) : 0;
    if (best == nullptr || out.ranking.empty() || n != fulls[out.ranking[0].layer].arrays->n_vertices()) {
        out.status = DS_PANIC;
        out.error = "the best match has no region of its layer's size";
        return;
    }
    out.region.resize(n);
    if ((st = ds_result_region(best, out.region.data(), n)) != DS_OK) {
        out.status = st;
        out.error = describe(st, "reading the best match failed");
        return;
    }
    out.warnings = warnings_of(best);
}

/// Run `job` on a worker thread while the calling thread forwards its progress to `cb` every
/// 100 ms as a percentage, with the text "<title>: <stage> (n%)"; `cb` returning false asks the
/// job to stop. Returns the message of an exception `job` threw ("" if none).
std::string run_on_worker(const std::function<void(Shared&)>& job, const std::string& title, vcg::CallBackPos* cb)
{
    Shared shared;
    std::string exception;
    auto body = [&]() {
        try {
            job(shared);
        } catch (const std::exception& e) {
            exception = e.what();
        }
        std::lock_guard<std::mutex> lock(shared.mutex);
        shared.done = true;
        shared.done_cv.notify_all();
    };

    std::thread worker;
    try {
        worker = std::thread(body);
    } catch (const std::exception&) {
        body(); // no thread available: run here, without live progress
        return exception;
    }

    int last_percent = -1;
    std::string last_stage;
    std::unique_lock<std::mutex> lock(shared.mutex);
    while (!shared.done) {
        shared.done_cv.wait_for(lock, std::chrono::milliseconds(100));
        if (shared.done || cb == nullptr) continue;
        const int percent = static_cast<int>(100.0 * std::min(1.0, std::max(0.0, shared.fraction)));
        // meshlabserver prints only the text, so the text carries the percentage too
        const std::string stage = title + ": " + shared.stage + " (" + std::to_string(percent) + "%)";
        if (percent == last_percent && stage == last_stage) continue;
        last_percent = percent;
        last_stage = stage;
        lock.unlock(); // the GUI callback processes events: do not hold the lock
        if (!cb(percent, stage.c_str())) shared.cancel.store(true);
        lock.lock();
    }
    lock.unlock();
    worker.join();
    return exception;
}

} // namespace

LocalizeOutcome run_localize(LocalizerCache& cache, int full_layer, const PackedLayer& full, const PackedLayer& partial,
                             const ds_options* options, vcg::CallBackPos* cb)
{
    LocalizeOutcome out;
    const std::string exception = run_on_worker(
        [&](Shared& shared) { localize_on_worker(cache, full_layer, full, partial, options, shared, out); },
        "Localize partial shape", cb);
    if (!exception.empty()) {
        out.status = DS_PANIC;
        out.error = "out of resources: " + exception;
    }
    return out;
}

SearchOutcome run_search(LocalizerCache& cache, const std::vector<SearchLayer>& fulls, const PackedLayer& partial,
                         const ds_options* options, vcg::CallBackPos* cb)
{
    SearchOutcome out;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string exception = run_on_worker(
        [&](Shared& shared) { search_on_worker(cache, fulls, partial, options, shared, out); }, "Rank layers", cb);
    if (!exception.empty()) {
        out.status = DS_PANIC;
        out.error = "out of resources: " + exception;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

} // namespace dsml
