// edsp-cueing: motion cueing (docs/cueing.md).
//   edsp-cueing offline --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                       [--csv-dir DIR] [--plot DIR] [--algorithm classical_washout|mpc] [--json]
//       each manoeuvre through a cueing algorithm at the cueing rate: every
//       setpoint through the kinematics' whole-path check, and what a rider
//       on the commanded platform perceives against the vehicle; with
//       --rig-effects, also on the platform's real motion (the setpoints
//       played through the stack and a rig with that file's [rig.effects]).
//   edsp-cueing omct --config FILE --cueing FILE [--json]
//       the Objective Motion Cueing Test's direct responses: gain and phase
//       per channel at the test's twelve frequencies.
//   edsp-cueing bench --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                     [--cycles 1000000] [--seed 1] [--variants 3] [--variant-seed 2026] [--json]
//       deploy/edsp bench cueing: per algorithm the manoeuvres' perception
//       errors (commanded and real, and over variants of them no setting was
//       chosen on), a soak of random vehicle motion counting refused
//       setpoints and the solve's time; their ratios; the OMCT.
//   edsp-cueing live --cueing FILE [--input udp|lcm] [--udp ADDRESS:PORT] [--config FILE] [--group FILE]
//                    [--session-id N]
//       the cueing source in a running group (live_command.h).
//   edsp-cueing send --manoeuvre FILE [--to ADDRESS:PORT|lcm] [--rate-hz 250] [--lead-s 5]
//                    [--after disengage|silence|estop|freeze|engage] [--tail-s 20] [--sent-log FILE]
//                    [--group FILE | --lcm-url URL] [--session-id N|auto]
//       a vehicle model's stand-in: the manoeuvre as packets, in real time (send_command.h).
//   edsp-cueing delay --log RUN.lcmlog --sent SENT.csv [--json]
//       each sample's delay from its sender to the drives, traced through the log (delay_command.h).
//   edsp-cueing score --log RUN.lcmlog --cueing FILE [--json]

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "bench_command.h"
#include "delay_command.h"
#include "live_command.h"
#include "offline_command.h"
#include "score_command.h"
#include "send_command.h"

int main(int argc, char** argv) {
  CLI::App app{"edsp-cueing: vehicle motion in, platform motion out (docs/cueing.md)"};
  app.require_subcommand(1);
  edsp::OfflineOptions offline;
  CLI::App* offline_command =
      app.add_subcommand("offline", "manoeuvres through classical washout, checked and scored offline");
  offline_command->add_option("--config", offline.config_path, "platform config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command->add_option("--cueing", offline.cueing_path, "cueing config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command->add_option("--manoeuvre", offline.manoeuvre_paths, "manoeuvre file(s) (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  offline_command
      ->add_option("--rig-effects", offline.rig_effects_path,
                   "score on the real motion too: a config whose [rig.effects] the rig has")
      ->check(CLI::ExistingFile);
  offline_command->add_option("--csv-dir", offline.csv_dir, "write <manoeuvre>.csv per manoeuvre here");
  offline_command->add_option("--plot", offline.plot_dir,
                              "draw <manoeuvre>.png per manoeuvre here: perceived, vehicle against platform");
  offline_command->add_option("--algorithm", offline.algorithm,
                              "classical_washout or mpc (default: the cueing config's [cueing] algorithm)");
  offline_command->add_flag("--json", offline.json, "JSON on stdout");
  std::string omct_config, omct_cueing;
  bool omct_json = false;
  CLI::App* omct_command = app.add_subcommand("omct", "the OMCT's direct responses of classical washout");
  omct_command->add_option("--config", omct_config, "platform config (TOML)")->required()->check(CLI::ExistingFile);
  omct_command->add_option("--cueing", omct_cueing, "cueing config (TOML)")->required()->check(CLI::ExistingFile);
  omct_command->add_flag("--json", omct_json, "JSON on stdout");
  edsp::BenchOptions bench;
  CLI::App* bench_command = app.add_subcommand("bench", "the cueing's figures (deploy/edsp bench cueing)");
  bench_command->add_option("--config", bench.offline.config_path, "platform config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--cueing", bench.offline.cueing_path, "cueing config (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--manoeuvre", bench.offline.manoeuvre_paths, "manoeuvre file(s) (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  bench_command->add_option("--rig-effects", bench.offline.rig_effects_path, "score on the real motion too")
      ->check(CLI::ExistingFile);
  bench_command->add_option("--cycles", bench.cycles, "cycles of random vehicle motion")
      ->check(CLI::Range(1, 10'000'000));
  bench_command->add_option("--seed", bench.seed, "the random vehicle's seed");
  bench_command->add_option("--variants", bench.variants, "variants of each manoeuvre scored too (0: none)")
      ->check(CLI::Range(0, 100));
  bench_command->add_option("--variant-seed", bench.variant_seed, "the variants' seed");
  bench_command->add_flag("--json", bench.offline.json, "JSON on stdout");
  edsp::LiveOptions live;
  CLI::App* live_command = app.add_subcommand("live", "the cueing source in a running group (EDSP_CUE_SETPOINT)");
  edsp::AddNodeOptions(live_command, &live.node);
  live_command->add_option("--cueing", live.cueing_path, "cueing config (TOML)")->required()->check(CLI::ExistingFile);
  live_command->add_option("--input", live.input, "the vehicle's samples: udp (--udp) or lcm (EDSP_VEHICLE)")
      ->capture_default_str()
      ->check(CLI::IsMember({"udp", "lcm"}));
  live_command->add_option("--udp", live.udp, "the vehicle's packets: ADDRESS:PORT (\"\": none)")
      ->capture_default_str();
  edsp::SendOptions send;
  CLI::App* send_command = app.add_subcommand("send", "a manoeuvre as the vehicle's packets, in real time");
  send_command->add_option("--manoeuvre", send.manoeuvre_path, "manoeuvre file (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  send_command->add_option("--to", send.to, "ADDRESS:PORT, or lcm: EDSP_VEHICLE on the group's bus")
      ->capture_default_str();
  send_command->add_option("--group", send.group_path, "with --to lcm: the bus of this group file")
      ->check(CLI::ExistingFile);
  send_command->add_option("--lcm-url", send.lcm_url, "with --to lcm: this LCM URL");
  send_command->add_option("--session-id", send.session, "with --to lcm: the session, or auto (from its traffic)")
      ->capture_default_str();
  send_command->add_option("--rate-hz", send.rate_hz, "packets per second")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 2000.0));
  send_command->add_option("--lead-s", send.lead_s, "at rest with engage first")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 600.0));
  send_command->add_option("--after", send.after, "then: disengage, silence, estop, freeze or engage")
      ->capture_default_str();
  send_command->add_option("--tail-s", send.tail_s, "for this long")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 600.0));
  send_command->add_option("--sent-log", send.sent_log_path, "CSV of each packet's sequence and send time");
  edsp::ScoreOptions score;
  CLI::App* score_command =
      app.add_subcommand("score", "a live run's cueing scored from its log: commanded and real motion");
  score_command->add_option("--log", score.log_path, "the group's log (.lcmlog)")->required()->check(CLI::ExistingFile);
  score_command->add_option("--cueing", score.cueing_path, "cueing config (TOML): the head, the vestibular models")
      ->required()
      ->check(CLI::ExistingFile);
  score_command->add_flag("--json", score.json, "JSON on stdout");
  edsp::DelayOptions delay;
  CLI::App* delay_command =
      app.add_subcommand("delay", "each vehicle sample's delay from its sender to the drives, from a group's log");
  delay_command->add_option("--log", delay.log_path, "the group's log (.lcmlog)")->required()->check(CLI::ExistingFile);
  delay_command->add_option("--sent", delay.sent_path, "edsp-cueing send --sent-log's CSV")
      ->required()
      ->check(CLI::ExistingFile);
  delay_command->add_flag("--json", delay.json, "JSON on stdout");
  CLI11_PARSE(app, argc, argv);
  try {
    if (live_command->parsed()) return edsp::RunLive(live);
    if (send_command->parsed()) return edsp::RunSend(send);
    if (delay_command->parsed()) return edsp::RunDelay(delay);
    if (score_command->parsed()) return edsp::RunScore(score);
    if (omct_command->parsed()) return edsp::RunOmctTable(omct_config, omct_cueing, omct_json);
    if (bench_command->parsed()) return edsp::RunBench(bench);
    return edsp::RunOffline(offline);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-cueing: %s\n", e.what());
    return 1;
  }
}
