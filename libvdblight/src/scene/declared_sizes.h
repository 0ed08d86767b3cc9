// The memory bound of scene loading (internal; docs/scene.md, "Memory bound").
//
// Many scene formats declare sizes inside the file (GLB chunk lengths, glTF byte lengths and
// accessor counts, FBX array lengths, COLLADA/OFF/.x counts, the binary STL triangle count),
// and Assimp allocates what they say before it reads the bytes: a 1 KB .glb could make a bake
// allocate 4 GB. checkDeclaredSizes reads those sizes first, checks each against the bytes
// that exist, and estimates what the importer will allocate from them; a file whose estimate
// exceeds sceneMemoryBound(file size) is refused with one line naming the file and the reason,
// before Assimp (or the PLY reader, which checks its own counts) sees it.
#pragma once

#include <cstdint>
#include <string>

namespace vdblight {

/// Bytes a scene loader may allocate for a file of `fileBytes`: max(256 MiB, 64 x size).
std::uint64_t sceneMemoryBound(std::uint64_t fileBytes);

/// Throws SceneError ("scene file 'PATH': REASON") if a size declared inside the file points
/// past the data that exists, or if what the importer would allocate from the declared sizes
/// exceeds sceneMemoryBound. `extension` is the lower-case extension with its dot (".glb").
/// Formats whose importer allocates in proportion to the bytes it reads are not scanned.
void checkDeclaredSizes(const std::string& path, const std::string& extension);

}  // namespace vdblight
