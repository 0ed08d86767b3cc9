// Reading glTF JSON (nlohmann::json, nlohmann-json3-dev) without trusting its shape: the glTF
// loaders read files Assimp has not yet checked (declared_sizes_gltf.cpp) or extensions it
// ignores (load_assimp.cpp), so a member may be missing or of any type. These accessors give
// "absent" (nullptr, an empty list) for the wrong type instead of nlohmann's exceptions or
// its iteration of a scalar as a one-element range. Internal to the scene module.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace vdblight::json {

using Json = nlohmann::json;

/// Parses a whole document; a discarded value (is_discarded()) if it is not valid JSON.
/// No exception: a bad document is the importer's to report.
inline Json parseOrDiscarded(const std::string& text) { return Json::parse(text, nullptr, /*allow_exceptions=*/false); }

/// The member `key` of an object; nullptr if `value` is absent, not an object or lacks it.
inline const Json* member(const Json* value, const char* key) {
    if (value == nullptr || !value->is_object()) return nullptr;
    const auto it = value->find(key);
    return it == value->end() ? nullptr : &*it;
}
inline const Json* member(const Json& value, const char* key) { return member(&value, key); }

/// The elements of an array; empty if `value` is absent or not an array.
inline const Json::array_t& elements(const Json* value) {
    static const Json::array_t kNone;
    return value != nullptr && value->is_array() ? value->get_ref<const Json::array_t&>() : kNone;
}

/// The members of an object (name -> value); empty if `value` is absent or not an object.
inline const Json::object_t& members(const Json* value) {
    static const Json::object_t kNone;
    return value != nullptr && value->is_object() ? value->get_ref<const Json::object_t&>() : kNone;
}

/// A number member as a double (integers and floats alike), or `fallback`.
inline double numberOr(const Json* value, double fallback) {
    return value != nullptr && value->is_number() ? value->get<double>() : fallback;
}

/// A string's text, or empty.
inline std::string stringOr(const Json* value) {
    return value != nullptr && value->is_string() ? value->get<std::string>() : std::string();
}

}  // namespace vdblight::json
