// vdblight info VOLUME: grids, resolution, bounds, node count, bytes and bake metadata.
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::app {

void addInfoCommand(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand("info", "Describe a baked volume: grids, resolution, bounds, metadata");
    cmd->add_option("volume", *path, "Volume (.vdb)")->required();
    cmd->add_flag("--json", *json, "Machine-readable JSON");
    cmd->callback([path, json] {
        bool prt = false;  // a PRT file holds samples and transfer, not a volume
        try {
            prt = isPrtFile(*path);
        } catch (const Error&) {
        }  // readVolume below reports unreadable files as before
        if (prt) return printPrtInfo(*path);
        TileId tile;
        if (readTileId(*path, tile)) {  // a tile of a bake (bake --tiles)
            const FileInfo info = inspectVolumeFile(*path);
            std::cout << (*json ? tileInfoJson(tile, info) : tileInfoText(tile, info));
            return;
        }
        ContentHash hash;  // the damage check's, reused: the file is hashed once
        const Volume volume = readVolume(*path, &hash);
        const FileInfo info = inspectVolumeFile(*path, &hash);
        std::cout << (*json ? volumeInfoJson(volume, info) : volumeInfoText(volume, info));
    });
}

}  // namespace vdblight::app
