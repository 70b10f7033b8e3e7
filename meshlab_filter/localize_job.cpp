#include "localize_job.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace dsml {
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
    std::atomic<bool> cancel{false};
};

/// `ds_progress_fn`: record the progress for the caller's thread; 0 asks the library to stop.
/// Runs on a library thread, so it never touches MeshLab (and never throws).
int record_progress(double fraction, const char* stage, void* user)
{
    auto* s = static_cast<Shared*>(user);
    try {
        std::lock_guard<std::mutex> lock(s->mutex);
        s->fraction = fraction;
        if (stage != nullptr) s->stage = stage;
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

/// The whole C-ABI sequence; runs on the worker thread, so that `ds_last_error_message`
/// (per thread) is read on the thread that failed.
void localize_on_worker(const PackedLayer& full, const PackedLayer& partial, const ds_options& options,
                        Shared& shared, LocalizeOutcome& out)
{
    ds_mesh* raw = nullptr;
    ds_status st = ds_mesh_create(full.xyz.data(), full.n_vertices(), full.tri.data(), full.n_faces(), &raw);
    MeshPtr full_mesh(raw);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "full layer rejected"); return; }

    raw = nullptr;
    st = ds_mesh_create(partial.xyz.data(), partial.n_vertices(), partial.tri.data(), partial.n_faces(), &raw);
    MeshPtr partial_mesh(raw);
    if (st != DS_OK) { out.status = st; out.error = describe(st, "partial layer rejected"); return; }

    ds_result* raw_result = nullptr;
    st = ds_localize(full_mesh.get(), partial_mesh.get(), &options, &record_progress, &shared, &raw_result);
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
        (st = ds_result_seconds(result.get(), &out.seconds)) != DS_OK) {
        out.status = st;
        out.error = describe(st, "reading the result failed");
    }
}

} // namespace

LocalizeOutcome run_localize(const PackedLayer& full, const PackedLayer& partial, const ds_options& options,
                             vcg::CallBackPos* cb)
{
    LocalizeOutcome out;
    Shared shared;
    auto body = [&]() {
        try {
            localize_on_worker(full, partial, options, shared, out);
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
