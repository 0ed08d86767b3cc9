// describeSceneSource (scene_load.h): how a scene file was read, in the words of the bake
// summaries, so that every command that loads a scene says it the same way.
#include <sstream>

#include "vdblight/scene/scene.h"

namespace vdblight {

std::string describeSceneSource(const SceneLoadReport& s) {
    std::ostringstream out;
    out << s.format << ": " << s.meshes << (s.meshes == 1 ? " mesh" : " meshes") << " in " << s.meshInstances
        << (s.meshInstances == 1 ? " instance" : " instances") << ", " << s.units << ", up axis " << s.up;
    if (s.defaultAlbedoOnly) out << ", no materials: default albedo 0.8";
    return out.str();
}

}  // namespace vdblight
