// PointExpression (include/sphdem/config/expression.hpp): a muParser parser
// bound to the variables x, y, z.
#include "sphdem/config/expression.hpp"

#include <muParser.h>

#include <numbers>
#include <stdexcept>

namespace sphdem {

struct PointExpression::Impl {
  mutable double x = 0, y = 0, z = 0;
  mu::Parser parser;
};

PointExpression::PointExpression(const std::string& text) : impl_(std::make_unique<Impl>()) {
  try {
    impl_->parser.DefineVar("x", &impl_->x);
    impl_->parser.DefineVar("y", &impl_->y);
    impl_->parser.DefineVar("z", &impl_->z);
    impl_->parser.DefineConst("pi", std::numbers::pi);
    impl_->parser.SetExpr(text);
    impl_->parser.Eval();  // muParser parses on the first evaluation
  } catch (const mu::Parser::exception_type& e) {
    throw std::invalid_argument(e.GetMsg());
  }
}

PointExpression::~PointExpression() = default;
PointExpression::PointExpression(PointExpression&&) noexcept = default;
PointExpression& PointExpression::operator=(PointExpression&&) noexcept = default;

double PointExpression::operator()(double x, double y, double z) const {
  impl_->x = x;
  impl_->y = y;
  impl_->z = z;
  return impl_->parser.Eval();
}

}  // namespace sphdem
