#pragma once
// An expression of the position x, y, z (muParser syntax: + - * / ^, sin,
// cos, exp, sqrt, ..., the constants _pi and pi, _e), evaluated by muParser
// (docs/case-file.md "initial_fields").
#include <memory>
#include <string>

namespace sphdem {

class PointExpression {
 public:
  // Throws std::invalid_argument with muParser's message (and the position
  // of the offending token) when the text is not a valid expression of x, y, z.
  explicit PointExpression(const std::string& text);
  ~PointExpression();
  PointExpression(PointExpression&&) noexcept;
  PointExpression& operator=(PointExpression&&) noexcept;

  double operator()(double x, double y, double z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;  // the parser keeps pointers to x, y, z: they must not move
};

}  // namespace sphdem
