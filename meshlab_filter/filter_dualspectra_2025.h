// MeshLab 2025.07 filter plugin (FilterPlugin): "Localize partial shape (dual spectra)", also
// the PyMeshLab filter `dualspectra_localize`. Selects, on a full mesh layer, the region that a
// partial (possibly deformed) mesh layer is. Only the 2025.07 interface is here: the parameters
// from the library's option table are option_parameters.h, the localization between two layers
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
    enum { FP_LOCALIZE_PARTIAL };

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
    /// Returns the result's numbers (PyMeshLab's dict): selected_vertices, selected_faces,
    /// confidence, cost, seconds, reused, warnings. Throws MLException, changing nothing, when
    /// the layers or an option cannot be used (the library's message).
    std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par, MeshDocument& md,
                                                unsigned int& postConditionMask, vcg::CallBackPos* cb) override;

private:
    /// Prepared full shapes, kept per full layer between calls (see dsml::LocalizerCache).
    dsml::LocalizerCache localizers;
};

#endif
