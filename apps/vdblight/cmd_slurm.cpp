// vdblight slurm SCENE -o WORLD.vdb --tiles N [bake options] [--sbatch "..."] [--submit]:
// a tiled bake (tiles.h) as a Slurm job array plus a merge job that runs after every tile
// succeeded (docs/scaling.md); a bake with probe-to-probe passes as one such pair per stage.
// The library writes the scripts (writeSlurmJobs) and reads their state (readSlurmJobs);
// this file parses the options, submits and prints.
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"

namespace vdblight::app {

namespace {
namespace fs = std::filesystem;

struct SlurmCommand {
    std::string scene;
    std::string output;
    int tiles = 0;
    std::string sbatch;  // extra sbatch options, e.g. "--partition=bake --cpus-per-task=8"
    bool submit = false;
    bool status = false;
};

std::string selfPath() {
    char buf[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) throw IoError("cannot find the path of the vdblight program (/proc/self/exe)");
    return std::string(buf, std::size_t(n));
}

std::string run(const std::string& command) {
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) throw IoError("cannot run '" + command + "'");
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = ::pclose(pipe);
    if (status != 0) throw IoError("'" + command + "' failed: " + out);
    return out;
}

void showStatus(const SlurmJobsState& state) {
    for (int s = 0; s < state.stages; ++s)
        std::cout << state.tilesOnDisk[std::size_t(s)] << " of " << state.tiles << " tiles on disk in " << state.directory
                  << (state.stages > 1 ? " (stage " + std::to_string(s) + " of 0.." + std::to_string(state.stages - 1) + ")" : "") << "\n";
    const std::vector<std::string>& ids = state.jobIds;
    if (ids.size() < 2) {
        std::cout << "not submitted (no " << (fs::path(state.directory) / "jobs").string() << ")\n";
        return;
    }
    std::string list;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        std::cout << (i % 2 ? ", merge: job " : "tiles: job ") << ids[i] << (i % 2 ? "\n" : "");
        list += (i ? "," : "") + ids[i];
    }
    std::cout << run("squeue -h -j " + list + " -o '  %i %T %M' 2>/dev/null || true")
              << run("sacct -n -X -j " + list + " -o JobID,State,Elapsed 2>/dev/null || true");
}
}  // namespace

void addSlurmCommand(CLI::App& app) {
    auto c = std::make_shared<SlurmCommand>();
    CLI::App* cmd = app.add_subcommand(
        "slurm", "Bake as a Slurm job array of tiles plus a merge job after them (options after -o/--tiles go to bake)");
    cmd->add_option("scene", c->scene, "Scene file (required first: the bake options follow)");
    cmd->add_option("-o,--output", c->output, "The merged .vdb; scripts and tiles go to OUTPUT.tiles/ (required)");
    cmd->add_option("--tiles", c->tiles, "Number of tiles (array tasks)");
    cmd->add_option("--sbatch", c->sbatch, "Extra sbatch options for every job, e.g. \"--partition=bake --cpus-per-task=8\"");
    cmd->add_flag("--submit", c->submit, "Submit the jobs with sbatch and print their ids");
    cmd->add_flag("--status", c->status,
                  "Report tiles on disk and the jobs' states (squeue / sacct): vdblight slurm --status WORLD.vdb");
    cmd->allow_extras();
    cmd->callback([c, cmd] {
        if (c->status && c->output.empty()) c->output = c->scene;  // slurm --status WORLD.vdb
        if (c->output.empty()) throw ValueError("slurm needs -o WORLD.vdb");
        if (c->status) return showStatus(readSlurmJobs(c->output));
        if (c->scene.empty()) throw ValueError("slurm needs the scene file first");
        if (c->tiles < 1) throw ValueError("--tiles must be at least 1");
        checkOutputWritable(fs::absolute(c->output).string());
        for (const std::string& a : cmd->remaining())
            if (a == "--tile" || a == "--tiles" || a == "-o" || a == "--output" || a == "--stage" || a == "--stage-input")
                throw ValueError("'" + a + "' is set by vdblight slurm itself");
        // Probe-to-probe passes read every node of the pass before: one job array per pass,
        // each after the merge of the one before (tiles.h, "Staged bakes").
        const int stages = bakeStageCount(c->scene, cmd->remaining());
        const std::string d =
            writeSlurmJobs({selfPath(), c->scene, c->output, c->tiles, stages, cmd->remaining(), c->sbatch});
        if (stages == 1)
            std::cout << "Wrote " << d << "/tiles.sbatch (array of " << c->tiles << " tiles), merge.sbatch and submit.sh.\n";
        else
            std::cout << "Wrote " << d << "/tiles-S.sbatch and merge-S.sbatch for stages S = 0.." << stages - 1 << " (arrays of "
                      << c->tiles << " tiles; stage S+1 reads the merged stage S) and submit.sh.\n";
        if (c->submit) std::cout << run("sh " + shellQuote(d + "/submit.sh"));
        else std::cout << "Submit with: sh " << shellQuote(d + "/submit.sh") << "\n";
    });
}

}  // namespace vdblight::app
