// The table of passes (pass.h): adding a pass is its file (pass_<name>.cpp), its function in
// passes.h and one entry here.
#include "passes.h"

#include "pass_options.h"
#include "vdblight/core/errors.h"

namespace vdblight {

const std::vector<const Pass*>& passRegistry() {
    using namespace bake_detail;
    static const std::vector<const Pass*> all = {&gatherPass(), &adaptivePass(), &antialiasedPass(),
                                                 &levelsPass(),  &binsPass(),     &photonsPass()};
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
