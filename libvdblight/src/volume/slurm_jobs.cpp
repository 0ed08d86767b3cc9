// A tiled bake as Slurm jobs (tiles.h: writeSlurmJobs, readSlurmJobs; `vdblight slurm`,
// docs/scaling.md): a job array of tiles plus a merge job that runs after every tile
// succeeded; a bake with probe-to-probe passes as one such pair per stage, each array after
// the merge before (array -> merge -> array -> merge, afterok). The scripts go to
// OUTPUT.tiles/ beside the output; the tiles are written there too, so that re-submitting
// redoes only the tiles not on disk (in every stage).
#include <filesystem>
#include <fstream>
#include <sstream>

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"

namespace vdblight {

namespace {
namespace fs = std::filesystem;

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

fs::path jobsDirectory(const std::string& output) { return fs::absolute(output).string() + ".tiles"; }
}  // namespace

std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

std::string writeSlurmJobs(const SlurmJobs& jobs) {
    const fs::path output = fs::absolute(jobs.output);
    const fs::path dir = jobsDirectory(jobs.output);
    const int stages = jobs.stages;
    std::string bakeArgs;
    for (const std::string& a : jobs.bakeArgs) bakeArgs += " " + shellQuote(a);
    fs::create_directories(dir);
    const std::string vdblight = shellQuote(jobs.program), d = dir.string();
    const std::string scene = shellQuote(fs::absolute(jobs.scene).string());
    const std::string extra = sbatchLines(jobs.sbatch);
    const std::string last = std::to_string(jobs.tiles - 1);
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
                        "tile-$SLURM_ARRAY_TASK_ID.vdb --tiles " + std::to_string(jobs.tiles) +
                        " --tile $SLURM_ARRAY_TASK_ID" + stageArgs + bakeArgs + "\n" + kRequeueOnSignal);
        std::string tiles;
        for (int t = 0; t < jobs.tiles; ++t) tiles += " " + shellQuote(d + "/" + prefix + "tile-" + std::to_string(t) + ".vdb");
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
    writeFileAtomically((dir / "tiles").string(), std::to_string(jobs.tiles) + " " + std::to_string(stages) + "\n");
    return d;
}

SlurmJobsState readSlurmJobs(const std::string& output) {
    const fs::path dir = jobsDirectory(output);
    SlurmJobsState state;
    state.directory = dir.string();
    std::ifstream count(dir / "tiles");
    if (!(count >> state.tiles)) throw IoError("no tiled bake for '" + output + "' (" + (dir / "tiles").string() + " missing)");
    count >> state.stages;
    state.stages = std::max(1, state.stages);
    for (int s = 0; s < state.stages; ++s) {
        int onDisk = 0;
        for (int t = 0; t < state.tiles; ++t) {
            TileId id;
            try {
                const fs::path tile = dir / (stagePrefix(s, state.stages) + "tile-" + std::to_string(t) + ".vdb");
                if (readTileId(tile.string(), id) && id.index == t) ++onDisk;
            } catch (const Error&) {
            }
        }
        state.tilesOnDisk.push_back(onDisk);
    }
    std::ifstream jobs(dir / "jobs");
    for (std::string id; jobs >> id;) state.jobIds.push_back(id);
    return state;
}

}  // namespace vdblight
