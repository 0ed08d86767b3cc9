// The table of passes (pass.h): adding a pass is its file (pass_<name>.cpp), its function in
// passes.h and one entry here.
#include "passes.h"

#include <algorithm>

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

std::vector<PassOptionEntry> passOptionTable() {
    std::vector<PassOptionEntry> table;
    for (const Pass* pass : passRegistry())
        for (const PassOption& o : pass->options()) {
            auto same = std::find_if(table.begin(), table.end(),
                                     [&](const PassOptionEntry& e) { return e.option.name == o.name; });
            if (same != table.end()) same->passes.push_back(pass->name());
            else table.push_back({o, {pass->name()}, {}});
        }
    for (PassOptionEntry& e : table) {
        std::string takers;
        for (const std::string& p : e.passes) takers += (takers.empty() ? "" : ", ") + p;
        e.help = e.option.help + " [pass" + (e.passes.size() > 1 ? "es " : " ") + takers + "]";
    }
    return table;
}

}  // namespace vdblight
