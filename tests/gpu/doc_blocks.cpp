#include "doc_blocks.h"

#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace vdblight::gpu {

std::vector<std::string> fencedBlocks(const std::string& markdown, const std::string& language) {
    std::vector<std::string> blocks;
    std::istringstream in(markdown);
    std::string line, block;
    bool inside = false;
    while (std::getline(in, line)) {
        if (!inside && line == "```" + language) {
            inside = true;
            block.clear();
        } else if (inside && line == "```") {
            inside = false;
            blocks.push_back(block);
        } else if (inside) {
            block += line + '\n';
        }
    }
    if (inside) throw std::runtime_error("an unterminated ```" + language + " block");
    return blocks;
}

const std::string& blockDeclaring(const std::vector<std::string>& blocks, const std::string& declaration) {
    const std::string* found = nullptr;
    for (const std::string& b : blocks)
        if (b.find(declaration) != std::string::npos) {
            if (found) throw std::runtime_error("two code blocks of the engine pages declare '" + declaration + "'");
            found = &b;
        }
    if (!found) throw std::runtime_error("no code block of the engine pages (docs/engine*.md) declares '" + declaration + "'");
    return *found;
}

const char* const kEngineDocs[3] = {"engines.md", "engine_layouts.md", "engine_visibility.md"};

std::string readEngineDocs() {
    std::string text;
    for (const char* page : kEngineDocs) text += readDoc(page) + "\n";
    return text;
}

std::string readDoc(const std::string& name) {
    const std::string path = std::string(VDBLIGHT_SOURCE_DIR) + "/docs/" + name;
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace vdblight::gpu
