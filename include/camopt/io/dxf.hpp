#pragma once
// DXF (R12, ASCII) export of a closed profile as one POLYLINE, read by CAD and cam-grinding
// software (AutoCAD DXF Reference, R12: ENTITIES section, POLYLINE / VERTEX / SEQEND)
#include <string>
#include <vector>

namespace camopt::io {

// closed 2-D polyline through (x, y) [mm] on `layer`
std::string dxf_closed_polyline(const std::vector<double>& x_mm, const std::vector<double>& y_mm,
                                const std::string& layer);

}  // namespace camopt::io
