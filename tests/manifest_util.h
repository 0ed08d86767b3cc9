// manifest.json of an export directory as a JSON value: tests check what it says, not how
// its text is laid out (export/manifest.cpp builds it with nlohmann::json).
#pragma once

#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace vdblight::test {

/// DIR/manifest.json parsed; std::runtime_error if it cannot be read, nlohmann's parse_error
/// if it is not JSON.
inline nlohmann::json readManifest(const std::string& dir) {
    std::ifstream in(dir + "/manifest.json");
    if (!in) throw std::runtime_error("cannot read " + dir + "/manifest.json");
    return nlohmann::json::parse(in);
}

/// DIR/manifest.json replaced by `manifest` (tests that hand a script a doctored manifest).
inline void writeManifest(const std::string& dir, const nlohmann::json& manifest) {
    std::ofstream out(dir + "/manifest.json", std::ios::trunc);
    out << manifest.dump(2) << "\n";
    if (!out) throw std::runtime_error("cannot write " + dir + "/manifest.json");
}

}  // namespace vdblight::test
