#include "option_parameters.h"

// The rich parameter classes: common/parameters/ from MeshLab 2021 on, common/filter_parameter/
// in 2020.09 (same classes, same constructors and getters as used here).
#if __has_include(<common/parameters/rich_parameter_list.h>)
#include <common/parameters/rich_parameter_list.h>
#else
#include <common/filter_parameter/rich_parameter_list.h>
#endif

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QStringList>

#include <algorithm>
#include <climits>
#include <vector>

namespace dsml {

namespace {

/// One option of the library's table: a filter parameter of the same name.
struct OptionParam {
    QString name, label, doc, type; ///< type: "int", "float" or "choice"
    QJsonValue defaultValue, min, max;
    QStringList choices;
};

/// The library's options, parsed once.
const std::vector<OptionParam>& optionParams()
{
    static const std::vector<OptionParam> params = [] {
        std::vector<OptionParam> out;
        const QJsonArray list = QJsonDocument::fromJson(QByteArray(ds_options_schema_json())).array();
        for (const QJsonValue& entry : list) {
            const QJsonObject o = entry.toObject();
            OptionParam p;
            p.name = o.value("name").toString();
            p.label = o.value("label").toString();
            p.doc = o.value("doc").toString();
            p.type = o.value("type").toString();
            p.defaultValue = o.value("default");
            p.min = o.value("min");
            p.max = o.value("max");
            for (const QJsonValue& c : o.value("choices").toArray()) p.choices << c.toString();
            out.push_back(p);
        }
        return out;
    }();
    return params;
}

/// The tooltip: the library's doc and the range.
QString tooltip(const OptionParam& p)
{
    if (p.type == "choice") return p.doc + " One of: " + p.choices.join(", ") + ".";
    const QString max = p.max.toDouble() >= double(INT_MAX) && p.type == "int" ? QString::number(INT_MAX)
                                                                                 : QString::number(p.max.toDouble());
    return p.doc + QString(" Range: %1 to %2.").arg(QString::number(p.min.toDouble()), max);
}

/// The parameter of `p` with the library's default.
std::unique_ptr<RichParameter> richParameter(const OptionParam& p)
{
    if (p.type == "int") {
        const double def = std::min(p.defaultValue.toDouble(), double(INT_MAX));
        return std::unique_ptr<RichParameter>(new RichInt(p.name, int(def), p.label, tooltip(p)));
    }
    if (p.type == "float")
        return std::unique_ptr<RichParameter>(new RichFloat(p.name, p.defaultValue.toDouble(), p.label, tooltip(p)));
    const int index = std::max(0, p.choices.indexOf(p.defaultValue.toString()));
    return std::unique_ptr<RichParameter>(new RichEnum(p.name, index, p.choices, p.label, tooltip(p)));
}

/// The value of `p` in `par` as the text the library parses; empty with `error` set if a
/// choice index is out of range.
QString parameterText(const OptionParam& p, const RichParameterList& par, QString& error)
{
    if (p.type == "int") return QString::number(par.getInt(p.name));
    if (p.type == "float") return QString::number(double(par.getFloat(p.name)), 'g', 7);
    const int i = par.getEnum(p.name);
    if (i < 0 || i >= p.choices.size()) {
        error = QString("%1: choice %2 is out of range (%3 choices: %4)")
                    .arg(p.name)
                    .arg(i)
                    .arg(p.choices.size())
                    .arg(p.choices.join(", "));
        return QString();
    }
    return p.choices[i];
}

} // namespace

size_t option_count()
{
    return optionParams().size();
}

void add_option_parameters(RichParameterList& par)
{
    for (const OptionParam& p : optionParams()) par.addParam(*richParameter(p));
}

OptionsPtr options_from_parameters(const RichParameterList& par, QString& error)
{
    if (optionParams().empty()) {
        error = "the library's option table could not be read";
        return nullptr;
    }
    ds_options* raw = nullptr;
    if (ds_options_create(&raw) != DS_OK) {
        error = QString("options: ") + QString::fromUtf8(ds_last_error_message());
        return nullptr;
    }
    OptionsPtr options(raw);
    for (const OptionParam& p : optionParams()) {
        const QString text = parameterText(p, par, error);
        if (!error.isEmpty()) return nullptr;
        if (ds_options_set(options.get(), qUtf8Printable(p.name), qUtf8Printable(text)) != DS_OK) {
            error = QString::fromUtf8(ds_last_error_message());
            return nullptr;
        }
    }
    return options;
}

} // namespace dsml
