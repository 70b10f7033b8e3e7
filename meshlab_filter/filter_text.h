// The words of the filters, the same in both plugin interfaces: their names (the menu entries,
// and the names a MeshLab script calls them by), their descriptions, and the labels and
// tooltips of the parameters that are not the library's options.
#ifndef DUALSPECTRA_MESHLAB_FILTER_TEXT_H
#define DUALSPECTRA_MESHLAB_FILTER_TEXT_H

#include <QString>

#include <dualspectra/dualspectra.h>

namespace dsml {

inline QString filter_name()
{
    return "Localize partial shape (dual spectra)";
}

/// The paper, and the library's version.
inline QString paper()
{
    return "<i>D. Bensa&iuml;d, A. Bracha, R. Kimmel</i><br>"
           "<b>\"Partial Shape Similarity by Multi-metric Hamiltonian Spectra Matching\"</b><br>"
           "SSVM 2023. Implementation: dualspectra " +
           QString(ds_version()) + ".";
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
           + paper();
}

inline QString search_filter_name()
{
    return "Rank layers by partial similarity (dual spectra)";
}

inline QString search_filter_info()
{
    return "Ranks every other visible mesh layer by how similar the <b>partial</b> layer is to a part of it: "
           "which of the models is the part (a fragment, a scan, a cut-off piece) from? The partial shape "
           "is located on each layer as <i>Localize partial shape</i> does, and each localization is "
           "scored (lower is more similar; scores of layers of different size and meshing compare). The "
           "log lists the ranking (rank, layer, score, confidence), and the region is selected on the "
           "best layer. Each layer's preparation is kept for the next call while its mesh and the "
           "options stay the same.<br>" +
           paper();
}

inline QString full_mesh_label() { return "Full mesh"; }
inline QString full_mesh_tooltip() { return "The complete shape. The matched region is selected on this layer."; }
inline QString partial_mesh_label() { return "Partial mesh"; }
inline QString partial_mesh_tooltip()
{
    return "The part to localize: a triangle mesh, possibly a deformed copy of a part of the full mesh. It must "
           "be a different layer with faces (not a point cloud).";
}
inline QString search_partial_mesh_tooltip()
{
    return "The part to look for on the other visible mesh layers: a triangle mesh, possibly a deformed copy "
           "of a part of one of them.";
}
inline QString write_score_label() { return "Score to vertex quality and colour"; }
inline QString write_score_tooltip()
{
    return "Also write the per-vertex membership score in [0, 1] to the vertex quality of the full mesh and "
           "colour it (red = in the region, blue = outside).";
}

} // namespace dsml

#endif
