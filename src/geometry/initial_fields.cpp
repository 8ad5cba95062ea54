// Initial fields from expressions (initial_fields.hpp), evaluated with
// muParser (include/sphdem/config/expression.hpp) in particle order.
#include "initial_fields.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sphdem/config/expression.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/sph/eos.hpp"

namespace sphdem {

namespace {

// Evaluates e at p; a value that is not finite is an input error at e.
template <int D>
double evaluate(const Case& c, const Expression& e, const PointExpression& f, const Vec<D>& p) {
  const double x = p[0], y = p[1], z = D == 3 ? p[D - 1] : 0.0;
  const double value = f(x, y, z);
  if (!std::isfinite(value)) {
    const std::string at = D == 3 ? fmt::format("({:.6g}, {:.6g}, {:.6g})", x, y, z)
                                  : fmt::format("({:.6g}, {:.6g})", x, y);
    throw InputError(c.source_file, e.line, e.key,
                     fmt::format("'{}' is {} at the resin particle at {}", e.text, value, at));
  }
  return value;
}

}  // namespace

template <int D>
void apply_initial_fields(const Case& c, const std::vector<std::size_t>& fill_of,
                          SphParticles<D>& ps) {
  const TaitEos eos(c.resin.density, c.resin.sound_speed, c.resin.gamma);
  std::vector<bool> touched(fill_of.size(), false);
  for (const InitialFields& item : c.initial_fields) {
    std::vector<PointExpression> vel;
    for (const Expression& e : item.velocity) vel.emplace_back(e.text);
    const std::optional<Expression>& scalar = item.density ? item.density : item.pressure;
    std::optional<PointExpression> rho_or_p, temp;
    if (scalar) rho_or_p.emplace(scalar->text);
    if (item.temperature) temp.emplace(item.temperature->text);
    for (std::size_t i = 0; i < fill_of.size(); ++i) {
      if (item.fill && fill_of[i] != static_cast<std::size_t>(*item.fill)) continue;
      touched[i] = true;
      for (int k = 0; k < D && !vel.empty(); ++k) {
        ps.v[i][k] = evaluate<D>(c, item.velocity[static_cast<std::size_t>(k)],
                                 vel[static_cast<std::size_t>(k)], ps.x[i]);
      }
      if (temp) {
        const double t = evaluate<D>(c, *item.temperature, *temp, ps.x[i]);
        if (!(t > 0)) {
          throw InputError(c.source_file, item.temperature->line, item.temperature->key,
                           fmt::format("gives the temperature {} K (not positive) at a resin "
                                       "particle",
                                       t));
        }
        ps.temperature[i] = t;
        ps.temp_half[i] = t;
      }
      if (!rho_or_p) continue;
      const double s = evaluate<D>(c, *scalar, *rho_or_p, ps.x[i]);
      const double rho = item.density ? s : eos.density(s);
      if (!(rho > 0) || !std::isfinite(rho)) {
        throw InputError(
            c.source_file, scalar->line, scalar->key,
            fmt::format("gives the density {} (not positive) at a resin particle", rho));
      }
      ps.rho[i] = rho;
    }
  }
  for (std::size_t i = 0; i < fill_of.size(); ++i) {
    if (!touched[i]) continue;
    ps.vwall[i] = ps.v[i];
    ps.v_half[i] = ps.v[i];
    ps.rho_half[i] = ps.rho[i];
  }
}

template void apply_initial_fields<2>(const Case&, const std::vector<std::size_t>&,
                                      SphParticles<2>&);
template void apply_initial_fields<3>(const Case&, const std::vector<std::size_t>&,
                                      SphParticles<3>&);

}  // namespace sphdem
