// MeshLab 2020.09 filter plugin (MeshFilterInterface): "Localize partial shape (dual spectra)".
// Selects, on a full mesh layer, the region that a partial (possibly deformed) mesh layer is.
// Only the 2020.09 interface is here: the parameters from the library's option table are
// option_parameters.h, the localization between two layers localize_layers.h, shared with the
// MeshLab 2025.07 plugin (filter_dualspectra_2025.h).
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
    enum { FP_LOCALIZE_PARTIAL };

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
    /// False, with `errorMessage` set and the same text logged as a warning (meshlabserver
    /// prints the log, not errorMessage).
    bool fail(const QString& message);

    /// Prepared full shapes, kept per full layer between calls (see dsml::LocalizerCache).
    dsml::LocalizerCache localizers;
};

#endif
