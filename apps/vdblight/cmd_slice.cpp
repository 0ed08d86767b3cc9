// vdblight slice VOLUME: an image of irradiance on a plane through the volume (slice.h).
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/slice.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::app {

namespace {
struct SliceCommand {
    std::string volume;
    std::string axis = "z";
    double at = 0.0;
    std::string normal;
    std::string output;
    int size = 256;
    std::string exposure = "auto";
    bool quiet = false;
};

void run(const SliceCommand& c) {
    SliceOptions o;
    if (c.axis.size() != 1 || c.axis.find_first_of("xyz") != 0)
        throw ValueError("--axis must be x, y or z, got '" + c.axis + "'");
    o.axis = c.axis[0] - 'x';
    o.at = c.at;
    o.normal = Vec3f(0, 0, 0);
    o.normal[o.axis] = 1.0f;  // default: the plane's own axis
    if (!c.normal.empty()) o.normal = Vec3f(parseTriple(c.normal, "--normal"));
    o.size = c.size;
    ToneMap tone;
    if (c.exposure != "auto") {
        tone.autoExposure = false;
        try {
            std::size_t used = 0;
            tone.exposure = std::stod(c.exposure, &used);
            if (used != c.exposure.size()) throw std::invalid_argument("trailing text");
        } catch (const std::exception&) {
            throw ValueError("--exposure must be 'auto' or a number of stops, got '" + c.exposure + "'");
        }
    }
    {
        const std::string ext = c.output.size() >= 4 ? c.output.substr(c.output.size() - 4) : "";
        if (ext != ".png" && ext != ".exr" && ext != ".PNG" && ext != ".EXR")
            throw ValueError("-o must name a .png (tone-mapped) or .exr (linear) file, got '" + c.output + "'");
    }
    checkOutputWritable(c.output);
    const Volume volume = readVolume(c.volume);
    const SliceImage image = sliceVolume(volume, o);
    writeSlice(c.output, image, tone, o.axis, o.at, o.normal);
    // Occlusion volumes include their lights' direct light (IrradianceQuery adds it); runtime
    // volumes hold indirect light only, which is what the image shows.
    if (volume.direct.mode == DirectMode::Runtime)
        std::cerr << "vdblight: note: '" << c.volume << "' was baked with --direct runtime: the slice shows its indirect "
                     "light only (the listed lights' direct light is added at run time)\n";
    if (!c.quiet)
        std::cout << "Wrote a " << image.width << " x " << image.height << " slice at " << c.axis << " = " << c.at
                  << " to " << c.output << "\n";
}
}  // namespace

void addSliceCommand(CLI::App& app) {
    auto c = std::make_shared<SliceCommand>();
    CLI::App* cmd = app.add_subcommand("slice", "Image of irradiance on a plane through the volume (.png or .exr)");
    cmd->add_option("volume", c->volume, "Volume (.vdb) written by vdblight bake")->required();
    cmd->add_option("--axis", c->axis, "Axis the plane is perpendicular to: x, y or z")->capture_default_str();
    cmd->add_option("--at", c->at, "World coordinate of the plane along --axis")->required();
    cmd->add_option("--normal", c->normal, "Surface normal nx,ny,nz for the irradiance (default: +axis)");
    cmd->add_option("-o,--output", c->output, "FILE.png (tone-mapped sRGB) or FILE.exr (linear W/m^2)")->required();
    cmd->add_option("--size", c->size, "Pixels along the longer image side")->capture_default_str();
    cmd->add_option("--exposure", c->exposure, "PNG exposure: auto (mean -> mid-grey) or stops on E/pi")
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", c->quiet, "Print nothing on success");
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
