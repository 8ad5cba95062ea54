#pragma once
// Shapes in a case file ({polygon: ...} or {box: {min, max}}) and the
// "is this region inside the mold" check (private to config/).
#include <optional>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/config/config.hpp"
#include "yaml_reader.hpp"

namespace sphdem::config {

// The keys of a shape and of a box, as the schema lists them; the readers
// below accept exactly these.
KeysDoc shape_keys_doc();
KeysDoc box_keys_doc();

// {polygon: [[x, y], ...]} (2D only) or {box: {min: [...], max: [...]}}.
Shape read_shape(const Value& v, int dim);
// A non-empty list of shapes.
std::vector<Shape> read_shape_list(const Value& v, int dim);
// {min: [...], max: [...]} with min < max along every axis.
Shape read_box(const Value& v, int dim);

// The first sample point of `region` (corners or vertices, and 8 points
// along every edge) outside the union of `mold`, if any. Points within
// 1e-9 of the mold's size from it count as inside.
std::optional<Vec3a> point_outside(const Shape& region, const std::vector<Shape>& mold, int dim);

// Whether `p` lies in the union of `mold` (with point_outside's tolerance).
bool inside_mold(const Vec3a& p, const std::vector<Shape>& mold, int dim);

}  // namespace sphdem::config
