// The words of the filter, the same in both plugin interfaces: its name (the menu entry, and
// the name a MeshLab script calls it by), its description, and the labels and tooltips of the
// parameters that are not the library's options.
#ifndef DUALSPECTRA_MESHLAB_FILTER_TEXT_H
#define DUALSPECTRA_MESHLAB_FILTER_TEXT_H

#include <QString>

#include <dualspectra/dualspectra.h>

namespace dsml {

inline QString filter_name()
{
    return "Localize partial shape (dual spectra)";
}

inline QString filter_info()
{
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
}

inline QString full_mesh_label() { return "Full mesh"; }
inline QString full_mesh_tooltip() { return "The complete shape. The matched region is selected on this layer."; }
inline QString partial_mesh_label() { return "Partial mesh"; }
inline QString partial_mesh_tooltip()
{
    return "The part to localize: a triangle mesh, possibly a deformed copy of a part of the full mesh. It must "
           "be a different layer with faces (not a point cloud).";
}
inline QString write_score_label() { return "Score to vertex quality and colour"; }
inline QString write_score_tooltip()
{
    return "Also write the per-vertex membership score in [0, 1] to the vertex quality of the full mesh and "
           "colour it (red = in the region, blue = outside).";
}

} // namespace dsml

#endif
