// Sizes declared inside scene files, checked before Assimp trusts them (declared_sizes.h).
//
// Per format, what Assimp 5.2.5 allocates from a declared size, and the check made here:
//  - GLB / glTF: chunk lengths (must lie inside the file), buffer byteLength (Assimp allocates
//    it: must fit the BIN chunk, the data: URI or the external file), buffer views and
//    accessors (must lie inside their view; an accessor without a view is zero-filled at its
//    declared count), and the meshes Assimp and our loader build from them: every primitive's
//    vertices and faces times the number of node instances that reach its mesh (a node
//    hierarchy that reuses children multiplies them; a cycle is refused).
//  - FBX binary: every array property's declared length (Assimp inflates into a buffer of
//    that size): raw arrays must hold exactly that many bytes, zlib arrays cannot inflate by
//    more than deflate's maximum ratio; the total is charged. FBX ASCII: every `*N` count.
//  - COLLADA: every count="N" attribute (Assimp reserves N values): N <= bytes in the file.
//  - OFF: the vertex and face counts of the header. STL (binary): the triangle count against
//    the file size. 3DS counts are 16-bit (at most 65535 items per chunk): not scanned.
//  - DirectX .x: MSZIP-compressed files are charged 32 KiB per block, as Assimp allocates;
//    integer tokens (Assimp resizes arrays to a count it reads) must not exceed the file
//    size (text) or bound / 32 (binary: one element is at most 32 bytes in Assimp).
//  - OBJ: Assimp's allocation follows the bytes it parses; counted per object/group/material
//    statement (each becomes a mesh). PLY: vdblight's own reader checks its counts.
#include "declared_sizes.h"

#include <algorithm>
#include <filesystem>

#include "declared_sizes_detail.h"

namespace vdblight {

std::uint64_t sceneMemoryBound(std::uint64_t fileBytes) {
    return std::max<std::uint64_t>(256 * declared_sizes::kMiB, 64 * fileBytes);
}

void checkDeclaredSizes(const std::string& path, const std::string& extension) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return;  // unreadable files are reported by the caller
    declared_sizes::Budget budget(path, size);
    using namespace declared_sizes;  // the scans: declared_sizes_detail.h
    if (extension == ".glb" || extension == ".gltf") {
        checkGltf(path, extension == ".glb", budget);
    } else if (extension == ".fbx") {
        const std::string d = readAll(path);
        if (d.compare(0, 18, "Kaydara FBX Binary") == 0) checkFbxBinary(d, budget);
        else checkFbxAscii(d, budget);
    } else if (extension == ".dae") {
        checkCollada(readAll(path), budget);
    } else if (extension == ".off") {
        checkOff(readAll(path), budget);
    } else if (extension == ".stl") {
        checkStl(readAll(path), budget);
    } else if (extension == ".x") {
        checkX(readAll(path), budget);
    } else if (extension == ".obj") {
        checkObj(path, budget);
    }
}

}  // namespace vdblight
