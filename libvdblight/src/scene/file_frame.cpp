// See file_frame.h.
#include "file_frame.h"

#include <cmath>
#include <sstream>

#include "vdblight/core/errors.h"

namespace vdblight {

FileFrame makeFileFrame(double metresPerUnit, bool zUp) {
    FileFrame f;
    const double s = metresPerUnit;
    if (zUp) {
        const double m[3][3] = {{s, 0, 0}, {0, 0, s}, {0, -s, 0}};
        for (int r = 0; r < 3; ++r) for (int c = 0; c < 3; ++c) f.m[r][c] = m[r][c];
    } else {
        for (int r = 0; r < 3; ++r) for (int c = 0; c < 3; ++c) f.m[r][c] = r == c ? s : 0.0;
    }
    return f;
}

void checkLoadOptions(const SceneLoadOptions& options) {
    if (!(std::isfinite(options.scale) && options.scale >= 0.0))
        throw ValueError("--scale must be a finite number of metres per file unit > 0, got " +
                         std::to_string(options.scale));
}

std::string describeUnit(double metresPerUnit) {
    std::ostringstream s;
    s.precision(6);
    s << "1 unit = " << metresPerUnit << " m";
    return s.str();
}

}  // namespace vdblight
