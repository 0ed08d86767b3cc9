// vdblight_bench_accuracy: table rows, the CSV, the worst points and the closing summary.
#include "accuracy.h"

#include <sys/resource.h>

namespace vdblight::accuracy {

void printRow(const Row& r) {
    char noise[32] = "";
    if (r.noise >= 0) std::snprintf(noise, sizeof noise, "%6.1f %%", 100 * r.noise);
    std::printf("  %-18s %7.1f %% %7.1f %% %8.1f %% %+7.1f %% %8.2f s %7.2f s %8llu %7.0f B %8s  %s\n", r.config.c_str(),
                100 * r.e.rms, 100 * r.e.p95, 100 * r.e.max, 100 * r.e.bias, r.seconds, r.cpu, (unsigned long long)r.nodes,
                r.bytesPerNode, noise, r.note.c_str());
}

void writeCsvRow(FILE* csv, const Row& r) {
    if (!csv) return;
    std::fprintf(csv, "%s,%s,%.5f,%.5f,%.5f,%.5f,%.3f,%.3f,%llu,%.1f,%s,%s\n", r.scene.c_str(), r.config.c_str(), r.e.rms,
                 r.e.p95, r.e.max, r.e.bias, r.seconds, r.cpu, (unsigned long long)r.nodes, r.bytesPerNode,
                 r.noise >= 0 ? std::to_string(r.noise).c_str() : "", r.note.c_str());
    std::fflush(csv);
}

/// The `count` points with the largest |error| (--worst N: where a method fails).
void printWorst(const std::vector<double>& rel, const std::vector<double>& got, const Truth& t, const Points& p, int count) {
    std::vector<std::size_t> order(rel.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(rel[a]) > std::abs(rel[b]); });
    for (int k = 0; k < count && k < int(order.size()); ++k) {
        const std::size_t i = order[std::size_t(k)];
        std::printf("    worst %d: x (%.3f, %.3f, %.3f) n (%.2f, %.2f, %.2f): E %.4g, E_ref %.4g +- %.2g, error %+.1f %%\n", k,
                    p.x[i].x, p.x[i].y, p.x[i].z, p.n[i].x, p.n[i].y, p.n[i].z, got[i], t.e[i], t.se[i], 100 * rel[i]);
    }
}

/// CPU seconds of this process (all threads): on a shared machine wall time includes waiting
/// for a core, CPU time does not.
double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

fs::path defaultCache(const char* argv0) {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) exe = fs::absolute(argv0);
    return exe.parent_path().parent_path() / "accuracy_cache";  // build/bin/.. = the build directory
}

void printSummary(const std::vector<Config>& configs, const std::vector<Row>& summary) {
    std::printf("\nSummary: RMS relative error (bias) per configuration and scene\n  %-18s", "config");
    std::vector<std::string> scenes;
    for (const Row& r : summary)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    for (const std::string& s : scenes) std::printf(" %20s", s.c_str());
    std::printf("\n");
    for (const Config& c : configs) {
        bool any = false;
        for (const Row& r : summary) any |= r.config == c.name;
        if (!any) continue;
        std::printf("  %-18s", c.name.c_str());
        for (const std::string& s : scenes) {
            const auto it = std::find_if(summary.begin(), summary.end(), [&](const Row& r) { return r.scene == s && r.config == c.name; });
            if (it == summary.end()) std::printf(" %20s", "-");
            else {
                char cell[40];
                std::snprintf(cell, sizeof cell, "%.1f %% (%+.1f %%)", 100 * it->e.rms, 100 * it->e.bias);
                std::printf(" %20s", cell);
            }
        }
        std::printf("\n");
    }
}

}  // namespace vdblight::accuracy
