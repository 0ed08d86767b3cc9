// vdblight merge TILE.vdb... -o WORLD.vdb: the tiles of one bake (bake --tiles N --tile I)
// put back together into the file a single-process bake writes (tiles.h).
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::app {

void addMergeCommand(CLI::App& app) {
    struct MergeCommand {
        std::vector<std::string> tiles;
        std::string output;
        bool quiet = false;
    };
    auto c = std::make_shared<MergeCommand>();
    CLI::App* cmd = app.add_subcommand(
        "merge", "Merge the tiles of a bake (bake --tiles N --tile I) into one .vdb, identical to a single bake");
    cmd->add_option("tiles", c->tiles, "Tile files, every tile of the bake exactly once, in any order")->required();
    cmd->add_option("-o,--output", c->output, "Output .vdb file (written atomically)")->required();
    cmd->add_flag("-q,--quiet", c->quiet, "No summary");
    cmd->callback([c] {
        checkOutputWritable(c->output);
        const MergedTiles merged = mergeTiles(c->tiles);
        writeVolume(merged.volume, c->output, merged.write);
        if (!c->quiet) {
            uint64_t nodes = 0;
            for (const VolumeLevel& l : merged.volume.levels) nodes += l.storedNodes();
            std::cout << "Merged " << c->tiles.size() << " tiles: " << nodes << " nodes in "
                      << merged.volume.levels.size() << (merged.volume.levels.size() == 1 ? " level" : " levels")
                      << ". Wrote " << c->output << " (content sha256 " << fileContentHash(c->output).sha256 << ").\n";
        }
    });
}

}  // namespace vdblight::app
