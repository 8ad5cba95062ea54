#include "scaling_command.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <thread>

#include "partition_command.hpp"
#include "scaling_rows.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem::app {

namespace {

namespace fs = std::filesystem;

InputError option_error(const std::string& option, const std::string& what) {
  return InputError(option, 0, "", what);
}

// One rank count of the study: the case's overrides and where its runs go.
struct Point {
  int ranks = 0;
  double spacing = 0;
  std::vector<std::string> sets;  // the user's, then the weak refinement
  fs::path dir;                   // <output>/ranks_<P>
};

fs::path run_dir(const Point& p, int k) {
  return p.dir / fmt::format("run_{}", k);
}
fs::path run_log(const Point& p, int k) {
  return p.dir / fmt::format("run_{}.log", k);
}

// Ranks the launcher can start without oversubscribing: --slots, else the
// batch system's allocation, else this machine's cores.
int available_slots(const ScalingArgs& a) {
  if (a.slots > 0) return a.slots;
  if (const char* n = std::getenv("SLURM_NTASKS")) return std::max(1, std::atoi(n));
  if (const char* f = std::getenv("PBS_NODEFILE")) {
    std::ifstream in(f);
    int lines = 0;
    for (std::string l; std::getline(in, l);) lines += !l.empty();
    if (lines > 0) return lines;
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// MemAvailable of /proc/meminfo (bytes), or --memory-gb.
double available_memory(const ScalingArgs& a) {
  if (a.memory_gb > 0) return a.memory_gb * 1e9;
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0;
  while (in >> key >> kb) {
    if (key == "MemAvailable:") return kb * 1024.0;
    in.ignore(256, '\n');
  }
  return static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// Bytes a run needs per particle: the estimate of `sphdem check` (fields,
// neighbour lists); the cluster-scale estimate of the case size will
// replace it.
double bytes_per_particle(int dim) {
  return dim * 8.0 * 7 + 8.0 * 8 + 4.0 * (dim == 2 ? 30 : 80);
}

// Resin + wall particles of the (unrefined) case, built as a run builds them.
template <int D>
std::int64_t lattice_particles(const Case& c) {
  SphParticles<D> ps;
  const InitialCounts n = build_initial_particles<D>(c, ps);
  return static_cast<std::int64_t>(n.fluid + n.wall);
}

// Fiber particles the case asks for: count x particles per fiber, or the
// area (volume) fraction of the region in particle disks (spheres).
double fiber_particles(const Case& c) {
  if (!c.fibers) return 0;
  const FiberSettings& f = *c.fibers;
  if (f.count > 0) return static_cast<double>(f.count) * f.particles_per_fiber;
  double region = 1;
  for (int d = 0; d < c.dimension; ++d) region *= f.region.hi[d] - f.region.lo[d];
  const double r = f.diameter / 2;
  const double particle =
      c.dimension == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return f.area_fraction * region / particle;
}

std::vector<int> parse_increasing_ranks(const std::string& text) {
  if (text.empty()) throw option_error("--ranks", "the rank list is empty (e.g. --ranks 1,2,4)");
  const std::vector<int> ranks = parse_rank_list(text);
  for (std::size_t i = 1; i < ranks.size(); ++i)
    if (ranks[i] <= ranks[i - 1])
      throw option_error("--ranks", fmt::format("must be increasing: {} follows {} in '{}'",
                                                ranks[i], ranks[i - 1], text));
  return ranks;
}

// Weak scaling: P ranks get the case with spacing / P^(1/D) (P times the
// resin particles) and P times the fibers, of the same size.
std::vector<std::string> weak_sets(const Case& c, int ranks, double spacing) {
  std::vector<std::string> sets{fmt::format("numerics.spacing={:.17g}", spacing)};
  if (c.fibers) {
    if (c.fibers->count > 0)
      sets.push_back(fmt::format("fibers.count={}", std::lround(c.fibers->count * ranks)));
    else
      sets.push_back(fmt::format("fibers.area_fraction={:.17g}", c.fibers->area_fraction * ranks));
  }
  return sets;
}

// A periodic length must stay a whole number of the refined spacings.
void check_periodic(const Case& c, const Box<3>& dom, int ranks, double spacing) {
  for (int k = 0; k < c.dimension; ++k) {
    if (!c.periodic[k]) continue;
    const double cells = (dom.hi[k] - dom.lo[k]) / spacing;
    if (std::abs(cells - std::round(cells)) > 1e-6)
      throw option_error(
          "--weak",
          fmt::format("at {} ranks the refined spacing {:.6g} m is not a whole fraction of the "
                      "periodic length along axis {} ({:.4f} spacings); use rank counts that "
                      "are {} (e.g. {})",
                      ranks, spacing, k, cells, c.dimension == 2 ? "squares" : "cubes",
                      c.dimension == 2 ? "1,4,16" : "1,8,64"));
  }
}

Box<3> domain_of(const Case& c) {
  Box<3> b{};
  if (c.dimension == 2) {
    const Box<2> d = simulation_domain<2>(c);
    for (int k = 0; k < 2; ++k) b.lo[k] = d.lo[k], b.hi[k] = d.hi[k];
  } else {
    b = simulation_domain<3>(c);
  }
  return b;
}

// Everything that can be checked before a run starts; InputError if not.
std::vector<Point> plan_study(const ScalingArgs& a) {
  const std::vector<int> ranks = parse_increasing_ranks(a.ranks);
  if (a.steps < 1) throw option_error("--steps", fmt::format("must be >= 1, got {}", a.steps));
  if (a.repeat < 1) throw option_error("--repeat", fmt::format("must be >= 1, got {}", a.repeat));
  if (a.launcher.find("{n}") == std::string::npos)
    throw option_error("--launcher", fmt::format("'{}' has no {{n}} for the rank count (e.g. "
                                                 "\"mpiexec -n {{n}}\", \"srun -n {{n}}\")",
                                                 a.launcher));
  const Case c = load_case(a.case_file, a.sets);
  if (!a.collect) {
    const bool oversubscribe = a.launcher.find("oversubscribe") != std::string::npos;
    const int slots = available_slots(a);
    if (!oversubscribe && ranks.back() > slots)
      throw option_error(
          "--ranks", fmt::format("{} ranks, but the launcher can start {} (--slots, SLURM_NTASKS, "
                                 "PBS_NODEFILE or the cores of this machine); add --oversubscribe "
                                 "to --launcher to run more ranks than cores",
                                 ranks.back(), slots));
  }
  const Box<3> dom = domain_of(c);
  std::vector<Point> points;
  for (int p : ranks) {
    Point pt{p, c.numerics.spacing, a.sets, fs::path(a.output_dir) / fmt::format("ranks_{}", p)};
    if (a.weak) {
      pt.spacing = c.numerics.spacing / std::pow(static_cast<double>(p), 1.0 / c.dimension);
      check_periodic(c, dom, p, pt.spacing);
      for (std::string& s : weak_sets(c, p, pt.spacing)) pt.sets.push_back(std::move(s));
    }
    points.push_back(std::move(pt));
  }
  if (a.collect) return points;
  // Memory: the largest case of the study (weak: P times the particles).
  const double base =
      static_cast<double>(c.dimension == 2 ? lattice_particles<2>(c) : lattice_particles<3>(c)) +
      fiber_particles(c);
  const double largest = base * (a.weak ? ranks.back() : 1);
  const double need = largest * bytes_per_particle(c.dimension);
  const double have = available_memory(a);
  if (need > have)
    throw option_error(
        a.weak ? "--weak" : "--ranks",
        fmt::format("the case at {} ranks has about {:.3g} particles and needs about {:.3g} GB, "
                    "more than the {:.3g} GB available ({} B per particle; --memory-gb sets the "
                    "memory of the launcher's nodes)",
                    ranks.back(), largest, need / 1e9, have / 1e9,
                    bytes_per_particle(c.dimension)));
  return points;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

std::string launch_command(const ScalingArgs& a, const Point& p, int k) {
  std::string launcher = a.launcher;
  for (std::size_t at; (at = launcher.find("{n}")) != std::string::npos;)
    launcher.replace(at, 3, std::to_string(p.ranks));
  const std::string exe = fs::read_symlink("/proc/self/exe").string();
  std::string cmd =
      fmt::format("{} {} run {} --steps {} -o {} --overwrite", launcher, shell_quote(exe),
                  shell_quote(a.case_file), a.steps, shell_quote(run_dir(p, k).string()));
  for (const std::string& s : p.sets) cmd += " --set " + shell_quote(s);
  return cmd + " > " + shell_quote(run_log(p, k).string()) + " 2>&1";
}

std::string read_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The row of run k of point p, from its log and timings.csv.
ScalingRow read_run(const Point& p, int k, int repeats) {
  ScalingRow r;
  r.ranks = p.ranks;
  r.spacing = p.spacing;
  r.run = k;
  r.repeats = repeats;
  try {
    r.counts = parse_run_log(read_text(run_log(p, k)));
    r.phases = read_timings(run_dir(p, k) / "timings.csv");
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("run {} on {} ranks ({}): {}", k, p.ranks, run_log(p, k).string(), e.what()));
  }
  if (r.phases.ranks != p.ranks)
    throw std::runtime_error(fmt::format("{}: {} ranks in timings.csv, expected {}",
                                         run_dir(p, k).string(), r.phases.ranks, p.ranks));
  return r;
}

// Runs point p `repeat` times (or, with --collect, reads the runs there)
// and keeps the least disturbed: the shortest wall time.
ScalingRow measure(const ScalingArgs& a, const Point& p, std::vector<ScalingRow>& all) {
  std::optional<ScalingRow> best;
  for (int k = 1; k <= a.repeat; ++k) {
    if (!a.collect) {
      fs::create_directories(p.dir);
      const std::string cmd = launch_command(a, p, k);
      const int status = std::system(cmd.c_str());
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
      if (code != 0) {
        throw std::runtime_error(
            fmt::format("the run on {} ranks exited with status {} (log: "
                        "{}):\n  {}",
                        p.ranks, code, run_log(p, k).string(), cmd));
      }
    }
    const ScalingRow r = read_run(p, k, a.repeat);
    std::cout << fmt::format("  {:>5} ranks, run {}/{}: {:.3f} s, {:.4g} particle-steps/s\n",
                             p.ranks, k, a.repeat, r.wall_seconds(), r.particle_steps_per_second())
              << std::flush;
    all.push_back(r);
    if (!best || r.wall_seconds() < best->wall_seconds()) best = r;
  }
  return *best;
}

// Weak scaling keeps the moving particles per rank within 5 % of the first
// point's; say so when the lattice rounding did not.
void check_weak_balance(const std::vector<ScalingRow>& rows) {
  const double first = static_cast<double>(rows.front().counts.moving()) / rows.front().ranks;
  for (const ScalingRow& r : rows) {
    const double per_rank = static_cast<double>(r.counts.moving()) / r.ranks;
    if (std::abs(per_rank / first - 1) > 0.05)
      std::cerr << fmt::format(
          "sphdem scaling: warning: {} ranks have {:.0f} resin + fiber particles per rank, {:+.1f} "
          "% from the {:.0f} of {} rank(s)\n",
          r.ranks, per_rank, 100 * (per_rank / first - 1), first, rows.front().ranks);
  }
}

void write_csv_file(const fs::path& file, const std::vector<ScalingRow>& rows,
                    const ScalingRow& base, bool weak) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::ofstream out(file);
  if (!out) throw option_error("--csv", fmt::format("cannot write '{}'", file.string()));
  write_scaling_csv(out, rows, base, weak);
}

int run_study(const ScalingArgs& a) {
  // Under mpiexec the launcher's environment would confuse the runs' own.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_RANK"))
    throw option_error("sphdem scaling",
                       "run it directly, not under mpiexec or srun: it starts "
                       "the runs through --launcher");
  const std::vector<Point> points = plan_study(a);
  std::cout << fmt::format("sphdem scaling: {} study of {}, {} steps, ranks {}, {} run(s) each\n",
                           a.weak ? "weak" : "strong", a.case_file, a.steps, a.ranks, a.repeat)
            << std::flush;
  if (a.dry_run) {
    for (const Point& p : points)
      for (int k = 1; k <= a.repeat; ++k) std::cout << launch_command(a, p, k) << "\n";
    return 0;
  }
  std::vector<ScalingRow> kept, all;
  for (const Point& p : points) kept.push_back(measure(a, p, all));
  const fs::path csv = a.csv.empty() ? fs::path(a.output_dir) / "scaling.csv" : fs::path(a.csv);
  write_csv_file(csv, kept, kept.front(), a.weak);
  write_csv_file(csv.parent_path() / (csv.stem().string() + "_all_runs.csv"), all, kept.front(),
                 a.weak);
  std::cout << fmt::format("{:>6} {:>12} {:>10} {:>14} {:>10}\n", "ranks", "particles", "wall [s]",
                           "part-steps/s", "efficiency");
  const double base = kept.front().particle_steps_per_second() / kept.front().ranks;
  for (const ScalingRow& r : kept)
    std::cout << fmt::format("{:>6} {:>12} {:>10.3f} {:>14.4g} {:>9.1f}%\n", r.ranks,
                             r.counts.all(), r.wall_seconds(), r.particle_steps_per_second(),
                             100 * r.particle_steps_per_second() / r.ranks / base);
  if (a.weak) check_weak_balance(kept);
  std::cout << "wrote " << csv.string() << "\n";
  return 0;
}

}  // namespace

CLI::App* add_scaling_command(CLI::App& app, ScalingArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "scaling",
      "Strong or weak scaling study of a case: runs it on each rank count through a launcher "
      "and writes one CSV row per rank count with the per-phase times (docs/scaling.md)");
  cmd->add_option("case", a.case_file, "Case file (YAML)")->required();
  cmd->add_option("--ranks", a.ranks, "Rank counts, comma-separated and increasing: --ranks 1,2,4")
      ->required();
  cmd->add_option("--steps", a.steps, "Steps of each run")->required();
  cmd->add_flag("--weak", a.weak,
                "Weak scaling: on P ranks numerics.spacing / P^(1/D) and P times the fibers "
                "(same size), so the particles per rank stay constant");
  cmd->add_option("--repeat", a.repeat,
                  "Runs per rank count; the shortest (least disturbed) is kept (default 1)");
  cmd->add_option("-o,--output", a.output_dir,
                  "Study directory: runs in ranks_P/run_K (log in run_K.log), scaling.csv "
                  "(default: scaling)");
  cmd->add_option("--csv", a.csv, "The CSV of the kept runs (default: OUTPUT/scaling.csv)");
  cmd->add_option("--launcher", a.launcher,
                  "How to start P ranks, {n} = P (default: \"mpiexec -n {n}\"; e.g. "
                  "\"mpiexec --oversubscribe -n {n}\", \"srun -n {n}\")");
  cmd->add_option("--slots", a.slots,
                  "Ranks the launcher can start (default: SLURM_NTASKS, the lines of PBS_NODEFILE, "
                  "or the cores of this machine); ignored with --oversubscribe in --launcher");
  cmd->add_option("--memory-gb", a.memory_gb,
                  "Memory of the launcher's nodes in all (default: this machine's available "
                  "memory)");
  cmd->add_option("--set", a.sets,
                  "Override a case key in every run: --set output.every_steps=1000")
      ->allow_extra_args(false);
  cmd->add_flag("--collect", a.collect,
                "Run nothing: write the CSV from the runs already in OUTPUT (job arrays, "
                "jobscripts/scaling_slurm.sh)");
  cmd->add_flag("--dry-run", a.dry_run,
                "Check the study (as before running it) and print the run commands; run nothing");
  cmd->footer(
      "Run it directly, not under mpiexec: it starts `sphdem run CASE --steps N` for each rank\n"
      "count through the launcher. Columns: ranks, spacing, resin, wall, fibers, dem (fiber\n"
      "particles), particles (resin + wall + dem), moving_per_rank ((resin + dem) / ranks),\n"
      "steps, wall_s (max over ranks), particle_steps_per_s, efficiency (particle-steps/s per\n"
      "rank relative to the first rank count), then per phase of timings.csv (compute, halo,\n"
      "migration, rebalance, io, wait, dem, coupling) its max and mean over ranks [s],\n"
      "step_lag_max and imbalance_max (the largest lag behind each step's slowest rank and the\n"
      "largest imbalance of the busy totals [s]), run, repeats. Bad input (rank list empty or\n"
      "not increasing, more ranks than slots, a weak study that would not fit memory) exits\n"
      "with status 2 before anything runs.");
  return cmd;
}

int scaling_main(int argc, char** argv) {
  CLI::App app{"sphdem: SPH-DEM simulator of injection molding of short-fiber composites"};
  app.require_subcommand(1);
  ScalingArgs a;
  add_scaling_command(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitInput;
  }
  try {
    return run_study(a);
  } catch (const InputError& e) {
    std::cerr << "sphdem: error: " << e.what() << "\n";
    return kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "sphdem scaling: " << e.what() << "\n";
    return kExitOther;
  }
}

}  // namespace sphdem::app
