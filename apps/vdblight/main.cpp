// vdblight: bake precomputed volumetric lighting into OpenVDB grids, and read it back.
// Every error the library throws is caught here once: one line on stderr, non-zero exit.
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "out_of_memory.h"

int main(int argc, char** argv) {
    vdblight::app::installMemoryReserve();
    try {
        // Inside the try, so that running out of memory while the commands are set up (under
        // `prlimit --as` at 173.5 MB) ends with the one line too.
        CLI::App app{"vdblight: precomputed volumetric lighting baked into OpenVDB grids"};
        app.require_subcommand(1);
        app.set_version_flag("--version", "vdblight 0.1.0 (volume format 1)");
        vdblight::app::addBakeCommand(app);
        vdblight::app::addQueryCommand(app);
        vdblight::app::addInfoCommand(app);
        vdblight::app::addReferenceCommand(app);
        vdblight::app::addExportCommand(app);
        vdblight::app::addSliceCommand(app);
        vdblight::app::addCheckSceneCommand(app);
        vdblight::app::addPrtCommand(app);
        vdblight::app::addMergeCommand(app);
        vdblight::app::addSlurmCommand(app);
        vdblight::app::installInterruptHandler();
        try {
            app.parse(argc, argv);
        } catch (const CLI::ParseError& e) {
            return app.exit(e);
        }
    } catch (const vdblight::Cancelled& e) {
        std::cerr << "vdblight: interrupted; no output written\n";
        return 130;
    } catch (const vdblight::OutOfMemory& e) {
        std::cerr << "vdblight: error: " << vdblight::app::outOfMemoryMessage(e.what()) << "\n";
        return 1;
    } catch (const vdblight::Error& e) {
        std::cerr << "vdblight: error: " << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "vdblight: error: " << vdblight::app::outOfMemoryMessage("") << "\n";
        return 1;
    } catch (const std::exception& e) {
        if (vdblight::app::threadStartFailedForMemory(e)) {  // a worker thread's stack did not fit
            std::cerr << "vdblight: error: " << vdblight::app::outOfMemoryMessage(e.what()) << "\n";
            return 1;
        }
        std::cerr << "vdblight: internal error: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
