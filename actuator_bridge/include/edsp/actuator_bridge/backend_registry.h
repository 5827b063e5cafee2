#pragma once
// Every drive backend the bridge can run, declared once by name (as
// ros2_control declares hardware by name): the name `--backend` and
// `[drives] backend` both give, whether it drives real encoders (and so
// needs `[drives] counts_per_m`), and how to make it. Adding a backend is
// one row here and its DriveBackend. An old spelling is still accepted,
// with a note naming the new one.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "edsp/actuator_bridge/drives_config.h"
#include "edsp/drive_io/drive_backend.h"
#include "edsp/transport/transport_config.h"

namespace edsp {

// What a backend is made from: [drives], the group's transport and the
// process image's prefix ("" = the transport's shm_prefix).
struct BackendContext {
  const DrivesConfig& drives;
  const TransportConfig& transport;
  std::string image_prefix;
};

struct BackendKind {
  std::string_view name;
  std::string_view description;
  bool real_drives;  // encoder counts: [drives] counts_per_m required
  std::unique_ptr<DriveBackend> (*make)(const BackendContext& context);
};

const std::vector<BackendKind>& BackendKinds();

// "virtual-rig, modbus-tcp, cia402-shm".
std::string KnownBackends();

// The row `name` names, or null. An old spelling finds its row and sets
// *note to a sentence naming the new one (else *note is cleared).
const BackendKind* FindBackend(const std::string& name, std::string* note);

// The backend `name` names, made, configured and activated for as long as
// this lives: deactivated and cleaned up when it goes, also when the loop
// that drives it throws, so no path out of the bridge leaves drives active.
class ActiveBackend {
 public:
  // Throws std::runtime_error naming the backend and why (an unknown name
  // with the known ones); an old spelling's note goes to *note.
  ActiveBackend(const std::string& name, const BackendContext& context, const PlatformConfig& config,
                std::string* note);
  ~ActiveBackend();
  ActiveBackend(const ActiveBackend&) = delete;
  ActiveBackend& operator=(const ActiveBackend&) = delete;

  DriveBackend& operator*() const { return *backend_; }
  DriveBackend* operator->() const { return backend_.get(); }
  DriveBackend* get() const { return backend_.get(); }

 private:
  std::unique_ptr<DriveBackend> backend_;
};

}  // namespace edsp
