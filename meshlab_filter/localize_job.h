// One call of the dualspectra C ABI (`ds_localize`) for two packed layers, with MeshLab's
// progress callback (`vcg::CallBackPos`) driven from the caller's thread. No MeshLab plugin
// interface types here: this file is the same for MeshLab 2020.09 and 2022+.
#ifndef DUALSPECTRA_MESHLAB_LOCALIZE_JOB_H
#define DUALSPECTRA_MESHLAB_LOCALIZE_JOB_H

#include <cstdint>
#include <string>
#include <vector>

#include <dualspectra/dualspectra.h>
#include <cstring> // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "layer_arrays.h"

namespace dsml {

/// What `run_localize` returns. `status == DS_OK` on success; otherwise `error` says why
/// (prefixed with the layer it concerns when the mesh itself was rejected).
struct LocalizeOutcome {
    ds_status status = DS_OK;
    std::string error;
    std::vector<uint8_t> region; ///< per packed vertex of the full layer: 1 = in the region
    std::vector<double> score;   ///< per packed vertex of the full layer, in [0, 1]
    double cost = 0.0;
    double seconds = 0.0;
};

/// Create the two C-ABI meshes and run `ds_localize` on a worker thread, while the calling
/// thread forwards the progress (`fraction`, `stage`) to `cb` every 100 ms as a percentage.
/// `cb` returning false cancels the computation (`DS_CANCELLED`). `cb` may be null.
/// Never throws: every failure is reported in the outcome.
LocalizeOutcome run_localize(const PackedLayer& full, const PackedLayer& partial, const ds_options& options,
                             vcg::CallBackPos* cb);

} // namespace dsml

#endif
