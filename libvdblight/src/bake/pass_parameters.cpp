// PassParameters (bake/bake.h): the passes' options in a request, by name, checked against
// the passes' declarations (Pass::options, gathered once from the registry).
#include <map>
#include <sstream>

#include "pass_options.h"
#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"

namespace vdblight {

namespace {
const char* kindName(PassOption::Kind kind) {
    switch (kind) {
        case PassOption::Kind::Number: return "a number";
        case PassOption::Kind::Word: return "a word";
        case PassOption::Kind::Flag: return "a flag";
    }
    return "";
}

PassOption::Kind kindOfValue(const PassValue& v) {
    if (std::holds_alternative<double>(v)) return PassOption::Kind::Number;
    if (std::holds_alternative<bool>(v)) return PassOption::Kind::Flag;
    return PassOption::Kind::Word;
}

/// The declaration of `name` (the first pass's that declares it: passOptionTable), or a
/// ValueError naming it. Built once; the presets (resolveBakeRequest) never come here, since
/// the declarations' help quotes them.
const PassOption& declaration(const std::string& name) {
    static const std::map<std::string, PassOption> declared = [] {
        std::map<std::string, PassOption> m;
        for (const PassOptionEntry& e : passOptionTable()) m.emplace(e.option.name, e.option);
        return m;
    }();
    const auto it = declared.find(name);
    if (it == declared.end()) throw ValueError("unknown bake option '" + name + "': no pass declares it");
    return it->second;
}

void checkKind(const PassOption& o, PassOption::Kind kind) {
    if (o.kind() != kind)
        throw ValueError("--" + o.name + " is " + kindName(o.kind()) + ", not " + kindName(kind));
}

/// The declared default as a value: a number, one of the words, a flag's "off"; none for a
/// default that depends on other options (the presets').
std::optional<PassValue> declaredDefault(const PassOption& o) {
    switch (o.kind()) {
        case PassOption::Kind::Flag:
            if (o.defaultValue == "off") return PassValue(false);
            return std::nullopt;
        case PassOption::Kind::Word:
            for (const std::string& c : o.choices)
                if (c == o.defaultValue) return PassValue(o.defaultValue);
            return std::nullopt;
        case PassOption::Kind::Number:
            try {
                return PassValue(bake_detail::parseOptionNumber(o.name, o.defaultValue, o.integer));
            } catch (const ValueError&) {
                return std::nullopt;
            }
    }
    return std::nullopt;
}
}  // namespace

PassParameters& PassParameters::setValue(const std::string& name, PassValue value) {
    const PassOption& o = declaration(name);
    checkKind(o, kindOfValue(value));
    if (const double* v = std::get_if<double>(&value); v && o.integer && !bake_detail::isWholeNumber(*v))
        throw ValueError("--" + name + " must be a whole number, got " + std::to_string(*v));
    if (const std::string* w = std::get_if<std::string>(&value); w && w->empty()) {
        values_.erase(name);  // no word is not given (`--domain ""`: the default)
        return *this;
    }
    values_[name] = std::move(value);
    return *this;
}

PassParameters& PassParameters::setText(const std::string& name, const std::string& text) {
    const PassOption& o = declaration(name);
    switch (o.kind()) {
        case PassOption::Kind::Flag:
            if (text == "true" || text == "1") return setValue(name, true);
            if (text == "false" || text == "0") return setValue(name, false);
            throw ValueError("--" + name + " is on or off (true or false), got '" + text + "'");
        case PassOption::Kind::Word:
            return setValue(name, text);  // an empty word unsets it there
        case PassOption::Kind::Number: {
            const double v = bake_detail::parseOptionNumber(name, text, o.integer);
            if (o.nonNegative && v < 0) throw ValueError("--" + name + " must not be negative, got " + text);
            return setValue(name, v);
        }
    }
    return *this;
}

PassParameters& PassParameters::unset(const std::string& name) {
    (void)declaration(name);
    values_.erase(name);
    return *this;
}

void PassParameters::outOfRange(const std::string& name, double value) {
    std::ostringstream text;
    text << value;
    throw ValueError("--" + name + " " + text.str() + " does not fit the type it is read as");
}

const PassValue* PassParameters::value(const std::string& name) const {
    const auto it = values_.find(name);
    return it == values_.end() ? nullptr : &it->second;
}

std::optional<PassValue> PassParameters::lookup(const std::string& name, PassOption::Kind kind, bool withDefault) const {
    // A value set was checked against its declaration then; its kind answers here, so that the
    // presets' help (which reads resolved requests while the declarations are built) never
    // needs the declarations.
    if (const PassValue* v = value(name)) {
        if (kindOfValue(*v) != kind)
            throw ValueError("--" + name + " is " + kindName(kindOfValue(*v)) + ", not " + kindName(kind));
        return *v;
    }
    const PassOption& o = declaration(name);
    checkKind(o, kind);
    if (!withDefault) return std::nullopt;
    std::optional<PassValue> d = declaredDefault(o);
    if (!d)
        throw ValueError("--" + name + " has no value: its default (" + o.defaultValue +
                         ") is filled in by resolveBakeRequest");
    return d;
}

}  // namespace vdblight
