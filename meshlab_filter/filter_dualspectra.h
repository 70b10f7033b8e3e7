// MeshLab 2020.09 filter plugin (MeshFilterInterface): "Localize partial shape (dual spectra)"
// selects, on a full mesh layer, the region that a partial (possibly deformed) mesh layer is;
// "Rank layers by partial similarity (dual spectra)" ranks the other visible layers for a
// partial layer and selects the region on the best. Only the 2020.09 interface is here: the
// parameters from the library's option table are option_parameters.h, the localization and
// the ranking localize_layers.h, shared with the MeshLab 2025.07 plugin
// (filter_dualspectra_2025.h).
#ifndef DUALSPECTRA_MESHLAB_FILTER_H
#define DUALSPECTRA_MESHLAB_FILTER_H

#include <common/interfaces.h>

#include "localize_job.h"

class FilterDualSpectraPlugin : public QObject, public MeshFilterInterface
{
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    enum { FP_LOCALIZE_PARTIAL, FP_RANK_LAYERS };

    FilterDualSpectraPlugin();

    QString pluginName() const override;
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* a) override;
    FILTER_ARITY filterArity(QAction* a) const override;
    int getPreConditions(QAction* a) const override;
    int postCondition(QAction* a) const override;
    void initParameterSet(QAction* a, MeshDocument& md, RichParameterList& par) override;
    bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

private:
    /// False, with `errorMessage` set (prefixed with the filter's name) and the same text
    /// logged as a warning (meshlabserver prints the log, not errorMessage).
    bool fail(const QString& prefix, const QString& message);
    /// A log line of the shared code: a warning or a filter line.
    void logLine(bool warning, const QString& line);

    /// Prepared full shapes, kept per full layer between calls (see dsml::LocalizerCache).
    dsml::LocalizerCache localizers;
};

#endif
