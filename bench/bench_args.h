// The command line of a benchmark program: `--quick` (the CI smoke run) and the program's own
// flags and options with one value, all optional, in any order. An unknown option or a
// missing value prints the usage line.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdblight::bench {

/// One option: `name` ("--threads") and what its value is ("N"); an empty `value` makes it a
/// flag, given without a value.
struct BenchOption {
    std::string name, value;
};

class BenchArgs {
public:
    /// `program` names the program in the usage line; `options` are those besides --quick.
    BenchArgs(std::string program, std::vector<BenchOption> options)
        : program_(std::move(program)), options_(std::move(options)) {
        options_.insert(options_.begin(), BenchOption{"--quick", ""});
    }

    /// Reads argv[1..argc). False (after printing "usage: PROGRAM [--quick] ..." to stderr) on
    /// an unknown option or an option without its value.
    bool parse(int argc, char** argv) {
        for (int i = 1; i < argc; ++i) {
            const BenchOption* o = find(argv[i]);
            if (o && o->value.empty()) values_[o->name] = "";
            else if (o && i + 1 < argc) values_[o->name] = argv[++i];
            else {
                std::string usage = "usage: " + program_;
                for (const BenchOption& u : options_) usage += " [" + u.name + (u.value.empty() ? "" : " " + u.value) + "]";
                std::fprintf(stderr, "%s\n", usage.c_str());
                return false;
            }
        }
        return true;
    }

    bool quick() const { return given("--quick"); }
    bool given(const std::string& name) const { return values_.count(name) != 0; }
    /// The option's value, or `fallback` if it was not given.
    std::string text(const std::string& name, const std::string& fallback = "") const {
        const auto it = values_.find(name);
        return it == values_.end() ? fallback : it->second;
    }
    /// The option's value read by std::atoi, or `fallback` if it was not given.
    int integer(const std::string& name, int fallback) const {
        return given(name) ? std::atoi(text(name).c_str()) : fallback;
    }

    /// The option's value read by std::atof, or `fallback` if it was not given.
    double real(const std::string& name, double fallback) const {
        return given(name) ? std::atof(text(name).c_str()) : fallback;
    }

private:
    const BenchOption* find(const std::string& name) const {
        for (const BenchOption& o : options_)
            if (o.name == name) return &o;
        return nullptr;
    }

    std::string program_;
    std::vector<BenchOption> options_;
    std::map<std::string, std::string> values_;
};

}  // namespace vdblight::bench
