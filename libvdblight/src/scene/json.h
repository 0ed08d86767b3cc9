// A small JSON reader for the glTF loaders (internal): enough to read the glTF extensions
// Assimp 5.2.5 ignores (KHR_materials_emissive_strength) and to check the sizes a glTF
// declares before Assimp trusts them (declared_sizes.cpp). Recursive descent, depth-bounded.
#pragma once

#include <cctype>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vdblight::json {

struct Json {
    enum Type { Null, Bool, Number, String, Array, Object } type = Null;
    double number = 0;
    std::string string;
    std::vector<Json> items;
    std::vector<std::pair<std::string, Json>> members;

    const Json* get(const std::string& key) const {
        for (const auto& m : members) if (m.first == key) return &m.second;
        return nullptr;
    }
};

/// Recursive descent over a complete document; throws std::runtime_error on bad syntax.
class JsonParser {
public:
    explicit JsonParser(const std::string& text) : s_(text) {}
    Json parse() { Json v = value(0); ws(); if (i_ != s_.size()) fail(); return v; }

private:
    [[noreturn]] void fail() const { throw std::runtime_error("bad JSON"); }
    void ws() { while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_; }
    bool eat(char c) { ws(); if (i_ < s_.size() && s_[i_] == c) { ++i_; return true; } return false; }
    void expect(char c) { if (!eat(c)) fail(); }

    Json value(int depth) {
        if (depth > 256) fail();
        ws();
        if (i_ >= s_.size()) fail();
        Json v;
        const char c = s_[i_];
        if (c == '{') {
            ++i_; v.type = Json::Object;
            if (eat('}')) return v;
            do {
                ws(); std::string key = str(); expect(':');
                v.members.emplace_back(std::move(key), value(depth + 1));
            } while (eat(','));
            expect('}');
        } else if (c == '[') {
            ++i_; v.type = Json::Array;
            if (eat(']')) return v;
            do v.items.push_back(value(depth + 1)); while (eat(','));
            expect(']');
        } else if (c == '"') {
            v.type = Json::String; v.string = str();
        } else if (s_.compare(i_, 4, "true") == 0 || s_.compare(i_, 5, "false") == 0) {
            v.type = Json::Bool; v.number = (c == 't'); i_ += (c == 't') ? 4 : 5;
        } else if (s_.compare(i_, 4, "null") == 0) {
            i_ += 4;
        } else {
            const char* begin = s_.c_str() + i_;
            char* end = nullptr;
            v.type = Json::Number; v.number = std::strtod(begin, &end);
            if (end == begin) fail();
            i_ += std::size_t(end - begin);
        }
        return v;
    }

    /// Escapes are kept only as far as keys need them; \uXXXX becomes '?'.
    std::string str() {
        if (i_ >= s_.size() || s_[i_] != '"') fail();
        std::string out;
        for (++i_; i_ < s_.size() && s_[i_] != '"'; ++i_) {
            if (s_[i_] != '\\') { out += s_[i_]; continue; }
            if (++i_ >= s_.size()) fail();
            const char e = s_[i_];
            if (e == 'u') { i_ += 4; out += '?'; }
            else out += (e == 'n') ? '\n' : (e == 't') ? '\t' : (e == 'r') ? '\r' : (e == 'b') ? '\b' : (e == 'f') ? '\f' : e;
        }
        if (i_ >= s_.size()) fail();
        ++i_;
        return out;
    }

    const std::string& s_;
    std::size_t i_ = 0;
};

}  // namespace vdblight::json
