// vdblight slurm SCENE -o WORLD.vdb --tiles N [bake options] [--sbatch "..."] [--submit]:
// a tiled bake (tiles.h) as a Slurm job array plus a merge job that runs after every tile
// succeeded (docs/scaling.md). The scripts go to WORLD.vdb.tiles/ beside the output; the
// tiles are written there too, so that re-submitting redoes only the tiles not on disk.
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/atomic_file.h"
#include "vdblight/errors.h"
#include "vdblight/tiles.h"

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

/// Single-quoted for sh.
std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

std::string selfPath() {
    char buf[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) throw IoError("cannot find the path of the vdblight program (/proc/self/exe)");
    return std::string(buf, std::size_t(n));
}

/// "--a=1 --b 2" -> "#SBATCH --a=1\n#SBATCH --b 2\n": one line per option.
std::string sbatchLines(const std::string& extra) {
    std::istringstream in(extra);
    std::string word, out, line;
    while (in >> word) {
        if (word[0] == '-' && !line.empty()) out += "#SBATCH " + line + "\n", line.clear();
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) out += "#SBATCH " + line + "\n";
    return out;
}

void writeScript(const fs::path& path, const std::string& text) {
    writeFileAtomically(path.string(), [&](const std::string& temp) {
        std::ofstream out(temp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw IoError("cannot write '" + temp + "'");
        fs::permissions(temp, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                        fs::perm_options::add);
    });
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

void showStatus(const fs::path& dir, int tiles) {
    int onDisk = 0;
    for (int t = 0; t < tiles; ++t) {
        TileId id;
        try {
            if (readTileId((dir / ("tile-" + std::to_string(t) + ".vdb")).string(), id) && id.index == t) ++onDisk;
        } catch (const Error&) {
        }
    }
    std::cout << onDisk << " of " << tiles << " tiles on disk in " << dir.string() << "\n";
    std::ifstream jobs(dir / "jobs");
    std::string tileJob, mergeJob;
    if (!(jobs >> tileJob >> mergeJob)) {
        std::cout << "not submitted (no " << (dir / "jobs").string() << ")\n";
        return;
    }
    std::cout << "tiles: job " << tileJob << ", merge: job " << mergeJob << "\n";
    std::cout << run("squeue -h -j " + tileJob + "," + mergeJob + " -o '  %i %T %M' 2>/dev/null || true")
              << run("sacct -n -X -j " + tileJob + "," + mergeJob + " -o JobID,State,Elapsed 2>/dev/null || true");
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
        const fs::path output = fs::absolute(c->output);
        const fs::path dir = output.string() + ".tiles";
        if (c->status) {
            std::ifstream count(dir / "tiles");
            int tiles = 0;
            if (!(count >> tiles)) throw IoError("no tiled bake for '" + c->output + "' (" + (dir / "tiles").string() + " missing)");
            return showStatus(dir, tiles);
        }
        if (c->scene.empty()) throw ValueError("slurm needs the scene file first");
        if (c->tiles < 1) throw ValueError("--tiles must be at least 1");
        checkOutputWritable(output.string());
        std::string bakeArgs;
        for (const std::string& a : cmd->remaining()) {
            if (a == "--tile" || a == "--tiles" || a == "-o" || a == "--output")
                throw ValueError("'" + a + "' is set by vdblight slurm itself");
            bakeArgs += " " + shellQuote(a);
        }
        fs::create_directories(dir);
        const std::string vdblight = shellQuote(selfPath()), d = dir.string();
        const std::string scene = shellQuote(fs::absolute(c->scene).string());
        const std::string extra = sbatchLines(c->sbatch);
        writeScript(dir / "tiles.sbatch",
                    "#!/bin/sh\n#SBATCH --job-name=vdblight-tiles\n#SBATCH --array=0-" + std::to_string(c->tiles - 1) +
                        "\n#SBATCH --requeue\n#SBATCH --output=" + d + "/tile-%a.log\n" + extra +
                        "# One tile per array task; a tile already on disk with the same parameters is skipped.\n"
                        "exec " + vdblight + " bake " + scene + " -o " + shellQuote(d) + "/tile-$SLURM_ARRAY_TASK_ID.vdb" +
                        " --tiles " + std::to_string(c->tiles) + " --tile $SLURM_ARRAY_TASK_ID" + bakeArgs + "\n");
        std::string tiles;
        for (int t = 0; t < c->tiles; ++t) tiles += " " + shellQuote(d + "/tile-" + std::to_string(t) + ".vdb");
        writeScript(dir / "merge.sbatch", "#!/bin/sh\n#SBATCH --job-name=vdblight-merge\n#SBATCH --output=" + d +
                                              "/merge.log\n" + extra + "exec " + vdblight + " merge" + tiles + " -o " +
                                              shellQuote(output.string()) + "\n");
        writeScript(dir / "submit.sh",
                    "#!/bin/sh\n# Submits the tiles as a job array and the merge to run after all of them succeeded.\nset -e\n"
                    "id=$(sbatch --parsable " + shellQuote(d + "/tiles.sbatch") + ")\nid=${id%%;*}\n"
                    "mid=$(sbatch --parsable --dependency=afterok:$id " + shellQuote(d + "/merge.sbatch") + ")\nmid=${mid%%;*}\n"
                    "echo \"$id $mid\" > " + shellQuote(d + "/jobs") + "\n"
                    "echo \"tiles: job $id (array 0-" + std::to_string(c->tiles - 1) + "), merge: job $mid (afterok:$id)\"\n");
        writeFileAtomically((dir / "tiles").string(), std::to_string(c->tiles) + "\n");
        std::cout << "Wrote " << d << "/tiles.sbatch (array of " << c->tiles << " tiles), merge.sbatch and submit.sh.\n";
        if (c->submit) std::cout << run("sh " + shellQuote(d + "/submit.sh"));
        else std::cout << "Submit with: sh " << shellQuote(d + "/submit.sh") << "\n";
    });
}

}  // namespace vdblight::app
