// vdblight slurm SCENE -o WORLD.vdb --tiles N [bake options] [--sbatch "..."] [--submit]:
// a tiled bake (tiles.h) as a Slurm job array plus a merge job that runs after every tile
// succeeded (docs/scaling.md); a bake with probe-to-probe passes as one such pair per stage,
// each array after the merge before (array -> merge -> array -> merge, afterok). The scripts
// go to WORLD.vdb.tiles/ beside the output; the tiles are written there too, so that
// re-submitting redoes only the tiles not on disk (in every stage).
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/atomic_file.h"
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

/// The end of a tile's job script: a bake killed by a signal (a kill, the OOM killer, a node
/// in trouble) puts its array task back into the queue, up to 3 times, so that the chain goes
/// on; a bake that stops with an error message exits with it (it would fail again). Slurm's
/// own --requeue covers node failures and `scontrol requeue`. A bake interrupted or terminated
/// (exit 130: vdblight's own SIGINT/SIGTERM handling; 143: SIGTERM before it) is not requeued:
/// that is `scancel`, whose SIGTERM need not reach this script before the bake has exited
/// (seen in slurm_cluster_test), and a cancelled tile stays cancelled.
const char* const kRequeueOnSignal =
    "rc=$?\n"
    "if [ $rc -gt 128 ] && [ $rc -ne 130 ] && [ $rc -ne 143 ] && [ \"${SLURM_RESTART_COUNT:-0}\" -lt 3 ]; then\n"
    "  echo \"vdblight slurm: the bake was killed by signal $((rc - 128)): requeueing tile $SLURM_ARRAY_TASK_ID\"\n"
    "  scontrol requeue \"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\"\n"
    "fi\n"
    "exit $rc\n";

/// Tile file and log names of stage `stage` of `stages` (one stage: the names before staging).
std::string stagePrefix(int stage, int stages) { return stages == 1 ? "" : "stage-" + std::to_string(stage) + "-"; }

void showStatus(const fs::path& dir, int tiles, int stages) {
    for (int s = 0; s < stages; ++s) {
        int onDisk = 0;
        for (int t = 0; t < tiles; ++t) {
            TileId id;
            try {
                if (readTileId((dir / (stagePrefix(s, stages) + "tile-" + std::to_string(t) + ".vdb")).string(), id) && id.index == t)
                    ++onDisk;
            } catch (const Error&) {
            }
        }
        std::cout << onDisk << " of " << tiles << " tiles on disk in " << dir.string()
                  << (stages > 1 ? " (stage " + std::to_string(s) + " of 0.." + std::to_string(stages - 1) + ")" : "") << "\n";
    }
    std::ifstream jobs(dir / "jobs");
    std::vector<std::string> ids;
    for (std::string id; jobs >> id;) ids.push_back(id);
    if (ids.size() < 2) {
        std::cout << "not submitted (no " << (dir / "jobs").string() << ")\n";
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
        const fs::path output = fs::absolute(c->output);
        const fs::path dir = output.string() + ".tiles";
        if (c->status) {
            std::ifstream count(dir / "tiles");
            int tiles = 0, stages = 1;
            if (!(count >> tiles)) throw IoError("no tiled bake for '" + c->output + "' (" + (dir / "tiles").string() + " missing)");
            count >> stages;
            return showStatus(dir, tiles, std::max(1, stages));
        }
        if (c->scene.empty()) throw ValueError("slurm needs the scene file first");
        if (c->tiles < 1) throw ValueError("--tiles must be at least 1");
        checkOutputWritable(output.string());
        std::string bakeArgs;
        for (const std::string& a : cmd->remaining()) {
            if (a == "--tile" || a == "--tiles" || a == "-o" || a == "--output" || a == "--stage" || a == "--stage-input")
                throw ValueError("'" + a + "' is set by vdblight slurm itself");
            bakeArgs += " " + shellQuote(a);
        }
        // Probe-to-probe passes read every node of the pass before: one job array per pass,
        // each after the merge of the one before (tiles.h, "Staged bakes").
        const int stages = bakeStageCount(c->scene, cmd->remaining());
        fs::create_directories(dir);
        const std::string vdblight = shellQuote(selfPath()), d = dir.string();
        const std::string scene = shellQuote(fs::absolute(c->scene).string());
        const std::string extra = sbatchLines(c->sbatch);
        const std::string last = std::to_string(c->tiles - 1);
        std::string submit = "#!/bin/sh\n# Submits the tiles as a job array and the merge to run after all of them succeeded" +
                             std::string(stages > 1 ? ", stage after stage" : "") + ".\nset -e\ndep=\nids=\n";
        for (int s = 0; s < stages; ++s) {
            const std::string prefix = stagePrefix(s, stages), suffix = stages == 1 ? "" : "-" + std::to_string(s);
            const std::string stageArgs =
                stages == 1 ? "" : " --stage " + std::to_string(s) + (s > 0 ? " --stage-input " + shellQuote(d + "/stage-" + std::to_string(s - 1) + ".vdb") : "");
            const std::string merged = s + 1 == stages ? output.string() : d + "/stage-" + std::to_string(s) + ".vdb";
            writeScript(dir / ("tiles" + suffix + ".sbatch"),
                        "#!/bin/sh\n#SBATCH --job-name=vdblight-tiles" + suffix + "\n#SBATCH --array=0-" + last +
                            "\n#SBATCH --requeue\n#SBATCH --open-mode=append\n#SBATCH --output=" + d + "/" + prefix + "tile-%a.log\n" + extra +
                            "# One tile per array task; a tile already on disk with the same parameters is skipped.\n" +
                            vdblight + " bake " + scene + " -o " + shellQuote(d) + "/" + prefix +
                            "tile-$SLURM_ARRAY_TASK_ID.vdb --tiles " + std::to_string(c->tiles) +
                            " --tile $SLURM_ARRAY_TASK_ID" + stageArgs + bakeArgs + "\n" + kRequeueOnSignal);
            std::string tiles;
            for (int t = 0; t < c->tiles; ++t) tiles += " " + shellQuote(d + "/" + prefix + "tile-" + std::to_string(t) + ".vdb");
            writeScript(dir / ("merge" + suffix + ".sbatch"),
                        "#!/bin/sh\n#SBATCH --job-name=vdblight-merge" + suffix + "\n#SBATCH --output=" + d + "/merge" + suffix +
                            ".log\n" + extra + "exec " + vdblight + " merge" + tiles + " -o " + shellQuote(merged) + "\n");
            submit += "id=$(sbatch --parsable $dep " + shellQuote(d + "/tiles" + suffix + ".sbatch") + ")\nid=${id%%;*}\n"
                      "mid=$(sbatch --parsable --dependency=afterok:$id " + shellQuote(d + "/merge" + suffix + ".sbatch") +
                      ")\nmid=${mid%%;*}\ndep=--dependency=afterok:$mid\nids=\"$ids $id $mid\"\n"
                      "echo \"" + (stages > 1 ? "stage " + std::to_string(s) + ": " : std::string()) + "tiles: job $id (array 0-" +
                      last + (s > 0 ? ", after the merge before" : "") + "), merge: job $mid (afterok:$id)\"\n";
        }
        submit += "echo $ids > " + shellQuote(d + "/jobs") + "\n";
        writeScript(dir / "submit.sh", submit);
        writeFileAtomically((dir / "tiles").string(), std::to_string(c->tiles) + " " + std::to_string(stages) + "\n");
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
