#include "localize_job.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
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

/// The whole C-ABI sequence; runs on the worker thread, so that `ds_last_error_message`
/// (per thread) is read on the thread that failed. The partial is checked first (cheap), then
/// the full shape is prepared if it must be, then the partial located.
void localize_on_worker(LocalizerCache& cache, int full_layer, const PackedLayer& full, const PackedLayer& partial,
                        const ds_options* options, Shared& shared, LocalizeOutcome& out)
{
    MeshPtr partial_mesh;
    ds_status st = make_mesh(partial, partial_mesh);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "partial layer rejected"); return; }

    const std::string key = cache_key(full, options);
    LocalizerCache::Localizer localizer = cache.find(full_layer, key);
    out.reused = localizer != nullptr;
    if (!localizer) {
        MeshPtr full_mesh;
        st = make_mesh(full, full_mesh);
        if (st != DS_OK) { out.status = st; out.error = describe(st, "full layer rejected"); return; }
        shared.enter(0.0, 0.3, "preparing the full shape: ");
        ds_localizer* raw = nullptr;
        st = ds_localizer_create(full_mesh.get(), options, &record_progress, &shared, &raw);
        localizer = LocalizerCache::Localizer(raw, ds_localizer_destroy);
        if (st != DS_OK) { out.status = st; out.error = describe(st, "preparing the full layer failed"); return; }
        cache.keep(full_layer, key, localizer);
        ds_localizer_preparation_seconds(localizer.get(), &out.preparation_seconds);
    }
    out.optimisation_vertices = ds_localizer_optimisation_vertices(localizer.get());

    shared.enter(out.reused ? 0.0 : 0.3, 1.0, "");
    ds_result* raw_result = nullptr;
    st = ds_localizer_locate(localizer.get(), partial_mesh.get(), &record_progress, &shared, &raw_result);
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
        (st = ds_result_seconds(result.get(), &out.seconds)) != DS_OK) {
        out.status = st;
        out.error = describe(st, "reading the result failed");
        return;
    }
    for (size_t i = 0; i < ds_result_n_warnings(result.get()); ++i) out.warnings.emplace_back(ds_result_warning(result.get(), i));
}

} // namespace

LocalizeOutcome run_localize(LocalizerCache& cache, int full_layer, const PackedLayer& full, const PackedLayer& partial,
                             const ds_options* options, vcg::CallBackPos* cb)
{
    LocalizeOutcome out;
    Shared shared;
    auto body = [&]() {
        try {
            localize_on_worker(cache, full_layer, full, partial, options, shared, out);
        } catch (const std::exception& e) {
            out.status = DS_PANIC;
            out.error = std::string("out of resources: ") + e.what();
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
        return out;
    }

    int last_percent = -1;
    std::string last_stage;
    std::unique_lock<std::mutex> lock(shared.mutex);
    while (!shared.done) {
        shared.done_cv.wait_for(lock, std::chrono::milliseconds(100));
        if (shared.done || cb == nullptr) continue;
        const int percent = static_cast<int>(100.0 * std::min(1.0, std::max(0.0, shared.fraction)));
        // meshlabserver prints only the text, so the text carries the percentage too
        const std::string stage = "Localize partial shape: " + shared.stage + " (" + std::to_string(percent) + "%)";
        if (percent == last_percent && stage == last_stage) continue;
        last_percent = percent;
        last_stage = stage;
        lock.unlock(); // the GUI callback processes events: do not hold the lock
        if (!cb(percent, stage.c_str())) shared.cancel.store(true);
        lock.lock();
    }
    lock.unlock();
    worker.join();
    return out;
}

} // namespace dsml
