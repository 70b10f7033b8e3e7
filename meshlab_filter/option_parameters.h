// The library's options as MeshLab filter parameters, for both plugin interfaces: one
// parameter per entry of the library's option table (`ds_options_schema_json`), with its name,
// label, default and doc (an integer is a RichInt, a number a RichFloat, a choice a RichEnum),
// and the values handed back to the library by name, as text (`ds_options_set`), so that an
// option added to the library appears in the filter without an edit. The rich parameter
// classes used here are the same in MeshLab 2020.09 and 2025.07 (only their header moved).
#ifndef DUALSPECTRA_MESHLAB_OPTION_PARAMETERS_H
#define DUALSPECTRA_MESHLAB_OPTION_PARAMETERS_H

#include <cstddef>
#include <memory>

#include <QString>

#include <dualspectra/dualspectra.h>

class RichParameterList;

namespace dsml {

/// The number of options in the library's table (0 only if its JSON were unreadable).
size_t option_count();

/// Append one parameter per option of the library's table to `par`, with the library's
/// defaults, in the table's order.
void add_option_parameters(RichParameterList& par);

struct OptionsDeleter {
    void operator()(ds_options* o) const { ds_options_destroy(o); }
};
using OptionsPtr = std::unique_ptr<ds_options, OptionsDeleter>;

/// Options holding the values of `par` (each handed to the library by name, as text; the
/// library checks it). On failure: null, and `error` says why (the library's message, naming
/// the option and its range, or a choice index out of range).
OptionsPtr options_from_parameters(const RichParameterList& par, QString& error);

} // namespace dsml

#endif
