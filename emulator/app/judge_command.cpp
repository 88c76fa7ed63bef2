// `gpsemu judge LOG [--json FILE] [--plots DIR]`: a fixed constant-velocity Kalman filter on the
// log and on simulated runs of every model calibrated from it (calibration/judge.hpp).
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/app/calibration_commands.hpp"
#include "emulator/calibration/judge.hpp"
#include "emulator/config/config.hpp"

namespace gpsemu {
namespace {

constexpr const char* kHelp =
    "judge the noise models by an estimator: run one fixed constant-velocity Kalman filter on a stationary "
    "receiver's log and on --runs simulated runs of every model calibrated from it, and compare NIS mean and "
    "95th percentile, innovation lag-1 autocorrelation and position error";

}  // namespace

Subcommand add_judge_command(CLI::App& app) {
  auto args = std::make_shared<CalibrationArgs>();
  CLI::App* sub = add_calibration_subcommand(app, "judge", kHelp, args);
  sub->add_option("--json", args->json, "also write the scores as JSON: {\"real\": {...}, \"models\": {NAME: {...}}, "
                  "\"best\": NAME}")->option_text("FILE");
  sub->add_option("--plots", args->plots, "also write judge_nis.csv and judge_summary.csv here for "
                  "tools/plot_noise.py judge DIR")->option_text("DIR");
  return {sub, [args](const Config& config, const std::atomic<bool>&) {
            const std::uint64_t seed = config.receiver().seed;
            calibration::ReceiverLog log = calibration::read_receiver_log_file(args->log);
            const calibration::Calibration c = calibration::calibrate(log, calibration_options(*args, seed));
            const calibration::Judgement j =
                calibration::judge(c, calibration::stated_sigma_m(log, c), args->runs, seed);
            std::fputs(calibration::receiver_state_summary(learned_receiver_state(args->log, c)).c_str(), stdout);
            std::fputs(calibration::judgement_table(j).c_str(), stdout);
            std::fputs(calibration::disagreement(j, c).c_str(), stdout);
            std::fputs(calibration::velocity_summary(c.velocity).c_str(), stdout);
            if (!args->json.empty()) {
              std::ofstream f(args->json);
              if (!f || !(f << calibration::judgement_json(j)) || !f.flush())
                throw std::runtime_error(fmt::format("--json: cannot write '{}'", args->json));
            }
            if (!args->plots.empty()) calibration::write_judgement_csv(j, args->plots);
            return 0;
          }};
}

}  // namespace gpsemu
