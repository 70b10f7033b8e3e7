// MeshLab 2025.07 filter plugin (FilterPlugin): "Localize partial shape (dual spectra)", also
// the PyMeshLab filter `dualspectra_localize`, selects, on a full mesh layer, the region that a
// partial (possibly deformed) mesh layer is; "Rank layers by partial similarity (dual
// spectra)", `dualspectra_search`, ranks the other visible layers for a partial layer and
// selects the region on the best. Only the 2025.07 interface is here: the parameters from the
// library's option table are option_parameters.h, the localization and the ranking
// localize_layers.h, shared with the MeshLab 2020.09 plugin (filter_dualspectra.h).
#ifndef DUALSPECTRA_MESHLAB_FILTER_2025_H
#define DUALSPECTRA_MESHLAB_FILTER_2025_H

#include <common/plugins/interfaces/filter_plugin.h>

#include "localize_job.h"

class FilterDualSpectraPlugin : public QObject, public FilterPlugin
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
    Q_INTERFACES(FilterPlugin)

public:
    enum { FP_LOCALIZE_PARTIAL, FP_RANK_LAYERS };

    FilterDualSpectraPlugin();

    QString pluginName() const override;
    QString vendor() const override;
    QString filterName(ActionIDType filter) const override;
    QString pythonFilterName(ActionIDType filter) const override;
    QString filterInfo(ActionIDType filter) const override;
    FilterClass getClass(const QAction* a) const override;
    FilterArity filterArity(const QAction* a) const override;
    int getPreConditions(const QAction* a) const override;
    int postCondition(const QAction* a) const override;
    RichParameterList initParameterList(const QAction* a, const MeshDocument& md) override;
    /// Returns the result's numbers (PyMeshLab's dict). Localize: selected_vertices,
    /// selected_faces, confidence, cost, optimisation_vertices, seconds, reused, warnings. Rank: best_layer (its id),
    /// score, confidence, selected_vertices, selected_faces, ranked (layers ranked), prepared,
    /// seconds. Throws MLException, changing nothing, when the layers or an option cannot be
    /// used (the library's message).
    std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par, MeshDocument& md,
                                                unsigned int& postConditionMask, vcg::CallBackPos* cb) override;

private:
    std::map<std::string, QVariant> localize(const RichParameterList& par, MeshDocument& md,
                                             unsigned int& postConditionMask, vcg::CallBackPos* cb);
    std::map<std::string, QVariant> rank(const RichParameterList& par, MeshDocument& md,
                                         unsigned int& postConditionMask, vcg::CallBackPos* cb);

    /// Prepared full shapes, kept per full layer between calls (see dsml::LocalizerCache).
    dsml::LocalizerCache localizers;
};

#endif
