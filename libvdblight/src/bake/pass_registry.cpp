// The table of passes (pass.h): adding a pass is a class in passes.h, its file, and one
// line here.
#include "passes.h"

#include "pass_options.h"
#include "vdblight/errors.h"

namespace vdblight {

const std::vector<const Pass*>& passRegistry() {
    static const bake_detail::GatherPass gather;
    static const bake_detail::AdaptivePass adaptive;
    static const bake_detail::AntialiasedPass antialiased;
    static const bake_detail::LevelsPass levels;
    static const bake_detail::BinsPass bins;
    static const bake_detail::PhotonsPass photons;
    static const std::vector<const Pass*> all = {&gather, &adaptive, &antialiased, &levels, &bins, &photons};
    return all;
}

const Pass& findPass(const std::string& name) {
    std::vector<std::string> names;
    for (const Pass* p : passRegistry()) {
        if (p->name() == name) return *p;
        names.push_back(p->name());
    }
    throw ValueError("unknown pass '" + name + "': the passes are " + bake_detail::joinChoices(names));
}

}  // namespace vdblight
