// The `output:`, `parallel:` and `checkpoint:` keys (docs/case-file.md):
// none of them changes a run's results, so none is in the checkpoint
// identity (docs/checkpoint.md).
#include <algorithm>

#include "schema.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem::config {

namespace {

void finish_output(const Map&, Output& o, Context& ctx) {
  output_defaults(o, ctx.c);
}

Key<Output> fields() {
  static const std::vector<std::string> kFields = sph_output_fields();  // the registry's
  std::string all;
  for (const std::string& f : kFields) all += (all.empty() ? "" : ", ") + f;
  Key<Output> k{"fields",
                "list",
                "",
                "",
                "each of " + all + ", at most once",
                "the resin's fields in every snapshot"};
  k.read = [](const Value& v, Output& o, Context&) {
    o.fields.clear();
    for (const Value& f : v.list()) {
      const std::string name = one_of(f, kFields);
      if (std::find(o.fields.begin(), o.fields.end(), name) != o.fields.end())
        f.fail("field '" + name + "' is listed twice");
      o.fields.push_back(name);
    }
  };
  k.show = [](const Output& o) {
    std::string out;
    for (const std::string& f : o.fields) out += (out.empty() ? "" : ", ") + f;
    return "[" + out + "]";
  };
  return k;
}

Section<Output> make_output() {
  Section<Output> s;
  s.keys = {
      string("directory", &Output::directory, "where snapshots, case.yaml and checkpoints go")
          .defaults_to("`out/<name>`"),
      optional_number("every_time", "s", positive_number(), &Output::every_time,
                      "simulated time between snapshots; at least the time step (a shorter one, "
                      "more than one snapshot per step, is refused)")
          .defaults_to("end_time / 100 if every_steps is absent too"),
      optional_integer("every_steps", "", 1, &Output::every_steps, "steps between snapshots"),
      fields(),
      integer("progress_every", "", 1, &Output::progress_every, "steps between progress lines"),
      boolean("front_events", &Output::front_events,
              "detect weld lines (the particle field `weld_line`) and trapped-air pockets; "
              "both listed in `<output>/<name>_front_events.csv`; see `docs/physics.md`"),
  };
  s.finish = finish_output;
  s.notes =
      "When both `every_time` and `every_steps` are given, a snapshot is written on\n"
      "either cadence.\n";
  return s;
}

Key<ParallelSettings> balance_weight() {
  Key<ParallelSettings> k{
      "balance_weight",
      "enum",
      "",
      "",
      "model or time",
      "what the imbalance check and a re-partition balance; model: the work counts above, "
      "the same decisions on every machine; time: the compute seconds each rank measured "
      "since the last check (the imbalance is theirs, and the new parts are sized by each "
      "rank's measured seconds per unit of work: ranks on slower or shared cores get less "
      "work; the decisions depend on the machine, the results do not); docs/parallel.md "
      "\"Balancing measured time\""};
  k.read = [](const Value& v, ParallelSettings& p, Context&) {
    p.balance_weight =
        one_of(v, {"model", "time"}) == "time" ? BalanceWeight::Time : BalanceWeight::Model;
  };
  k.show = [](const ParallelSettings& p) {
    return p.balance_weight == BalanceWeight::Time ? "time" : "model";
  };
  return k;
}

Section<ParallelSettings> make_parallel() {
  using P = ParallelSettings;
  Section<P> s;
  s.keys = {
      integer("balance_every", "steps", 0, &P::balance_every,
              "the imbalance is measured at the first neighbor rebuild at least this many steps "
              "after the last measurement (the work per rank changes only when particles "
              "migrate, which happens at rebuilds); 0: never re-partition"),
      number("imbalance_threshold", "", non_negative_number(), &P::imbalance_threshold,
             "re-partition when the largest per-rank work exceeds the mean by more than this "
             "fraction (work: 10 per resin particle, 3 per wall particle with resin in its "
             "top-level cell or the next, 1 per other wall particle and, in a coupled run, 5 x "
             "the last step's DEM sub-steps per fiber particle; docs/parallel.md \"Which "
             "weights, when\")"),
      balance_weight(),
      integer("min_top_cells", "", 1, &P::min_top_cells,
              "the decomposition partitions top-level cells, blocks of b^D neighbor-search "
              "cells with the smallest b that leaves at most max(top_cells_per_rank x ranks, "
              "this) of them; every rank holds their owners, rank 0 partitions their graph (a "
              "smaller value: coarser blocks, less memory, a rougher balance)"),
      integer("top_cells_per_rank", "", 1, &P::top_cells_per_rank,
              "top-level cells per rank once the ranks times this exceed min_top_cells (SWIFT "
              "uses a few tens)"),
  };
  s.intro =
      "How the decomposition follows the resin when a run uses several MPI ranks\n"
      "(`docs/parallel.md`). The keys change only the speed of a run, never its\n"
      "results: a run gives the same particle states at every rank count.\n";
  s.notes =
      "When a re-partition happens, rank 0 logs one line with the imbalance before\n"
      "and after and the number of particles that moved.\n";
  return s;
}

Section<CheckpointSettings> make_checkpoint() {
  using K = CheckpointSettings;
  Section<K> s;
  s.keys = {
      optional_integer("every_steps", "steps", 1, &K::every_steps,
                       "a checkpoint after every step that is a multiple of it; "
                       "`--checkpoint-every N` overrides it"),
      optional_number("every_minutes", "min", positive_number(), &K::every_minutes,
                      "a checkpoint once this much wall-clock time has passed since the last one "
                      "(rank 0's clock decides for all ranks)"),
      integer("keep", "", 1, &K::keep,
              "the newest checkpoints kept in `<output>/checkpoints/`, older ones deleted"),
  };
  s.intro =
      "Checkpoints for restarting a run (`docs/checkpoint.md`). Without a cadence\n"
      "(here or `sphdem run --checkpoint-every N`) a run writes a checkpoint only\n"
      "when asked to stop by SIGTERM or SIGUSR1. With one, it also writes one at its\n"
      "last step, so a run stopped by `--steps` or `end_time` can be continued.\n";
  s.notes =
      "When both cadences are given, a checkpoint is written on either. These keys,\n"
      "the `output` and `parallel` keys and `numerics.end_time` may change between\n"
      "a run and its restart; any other change is refused (`docs/checkpoint.md`).\n";
  return s;
}

}  // namespace

void output_defaults(Output& o, const Case& c) {
  if (o.directory.empty()) o.directory = "out/" + c.name;
  if (!o.every_time && !o.every_steps) o.every_time = c.numerics.end_time / 100;
}

const Section<Output>& output_keys() {
  static const Section<Output> s = make_output();
  return s;
}

const Section<ParallelSettings>& parallel_keys() {
  static const Section<ParallelSettings> s = make_parallel();
  return s;
}

const Section<CheckpointSettings>& checkpoint_keys() {
  static const Section<CheckpointSettings> s = make_checkpoint();
  return s;
}

}  // namespace sphdem::config
