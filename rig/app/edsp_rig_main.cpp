// edsp-rig: the virtual EDSP standing in for hardware. Serves the drives'
// shared-memory process image to the actuator bridge, steps servo loops,
// screws with true signed PR and the platform at 1 kHz, and publishes the
// laser tracker (EDSP_TRACKER) and ground truth (EDSP_RIG_TRUTH).
//   edsp-rig [--tracker-noise-m 0] [--tracker-rate-hz 1000] [--seed 1]
//            [--tracker-frame x,y,z,roll,pitch,yaw] [--image-prefix edsp]
//            [--drive-watchdog-ms 20] [--config FILE] [--group FILE]
// Drives whose process image stops updating (a frozen or dead bridge) stop
// interpolating after 4 ms and hold; past --drive-watchdog-ms they report
// holding, and EDSP_FAULT says so (and again, as info, when commands return).
// The rig on its bus and image: RigLoop (edsp/rig/rig_loop.h).
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/pose_text.h"
#include "edsp/node/node_options.h"
#include "edsp/node/runtime.h"
#include "edsp/rig/drive_image_server.h"
#include "edsp/rig/rig_effects.h"
#include "edsp/rig/rig_loop.h"
#include "edsp/rig/virtual_rig.h"
#include "edsp/transport/bus.h"

namespace edsp {
namespace {

int Run(int argc, char** argv) {
  NodeApp app{"edsp-rig: the virtual EDSP with a laser-tracker emulator"};
  RigParameters rig_parameters;
  std::string frame_text, image_prefix;
  app.add_option("--tracker-noise-m", rig_parameters.tracker.noise_sigma_m, "1-sigma per axis")
      ->check(CLI::Range(0.0, 0.01));
  app.add_option("--tracker-rate-hz", rig_parameters.tracker.rate_hz)->check(CLI::Range(1.0, 1000.0));
  app.add_option("--seed", rig_parameters.tracker.seed, "noise seed");
  app.add_option("--tracker-frame", frame_text, "pose of {B} in the tracker frame, x,y,z,roll,pitch,yaw");
  app.add_option("--image-prefix", image_prefix, "process image segment prefix (default: shm_prefix)");
  double watchdog_ms = rig_parameters.watchdog.timeout_s * 1e3;
  app.add_option("--drive-watchdog-ms", watchdog_ms, "no command for this long: the drives report holding")
      ->check(CLI::Range(5.0, 10000.0));
  CLI11_PARSE(app, argc, argv);
  rig_parameters.watchdog.timeout_s = watchdog_ms * 1e-3;

  const PlatformConfig config = LoadConfigFile(app.node.config_path);
  rig_parameters.nominal = config;
  rig_parameters.effects = LoadRigEffects(app.node.config_path);  // [rig.effects]: how this rig differs
  if (!frame_text.empty()) rig_parameters.tracker.X_TB = ParsePoseText(frame_text);
  const TransportConfig transport = TransportFor(app.node);
  InstallStopSignals();
  VirtualRig rig(rig_parameters);
  const std::string prefix = image_prefix.empty() ? transport.shm_prefix : image_prefix;
  const ImageRestore restore = RestoreFromImage(prefix, transport.shm_permissions, &rig);
  DriveImageServer image(prefix, transport.shm_permissions);
  Bus bus(transport);
  RigLoop loop(bus, rig, image, restore);
  RateClock clock(kRigPeriod, kRigPhase);
  loop.Run(clock, StopRequested);
  return 0;
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) { return edsp::RunMain("edsp-rig", edsp::Run, argc, argv); }
