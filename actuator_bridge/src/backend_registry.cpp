#include "edsp/actuator_bridge/backend_registry.h"

#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/actuator_bridge/cia402_backend.h"
#include "edsp/actuator_bridge/virtual_rig_backend.h"
#include "edsp/drives/csp_shm_master.h"
#include "edsp/drives/modbus_drive_master.h"

namespace edsp {

namespace {

std::string ImagePrefix(const BackendContext& c) {
  return c.image_prefix.empty() ? c.transport.shm_prefix : c.image_prefix;
}

std::unique_ptr<DriveBackend> MakeVirtualRig(const BackendContext& c) {
  return std::make_unique<VirtualRigBackend>(ImagePrefix(c), c.transport.shm_permissions);
}

std::unique_ptr<DriveBackend> MakeModbusTcp(const BackendContext& c) {
  return std::make_unique<Cia402Backend>(
      c.drives, std::make_unique<cia402::ModbusDriveMaster>(c.drives.host, c.drives.port, c.drives.response_timeout_s));
}

std::unique_ptr<DriveBackend> MakeCia402Shm(const BackendContext& c) {
  return std::make_unique<Cia402Backend>(
      c.drives,
      std::make_unique<cia402::CspShmMaster>(ImagePrefix(c), c.transport.shm_permissions, c.drives.response_timeout_s));
}

struct OldSpelling {
  std::string_view old_name, name;
};
constexpr OldSpelling kOldSpellings[] = {{"virtual", "virtual-rig"}};

}  // namespace

const std::vector<BackendKind>& BackendKinds() {
  static const std::vector<BackendKind> kinds = {
      {"virtual-rig", "the virtual rig's process image in shared memory (edsp-rig)", false, MakeVirtualRig},
      {"modbus-tcp", "six CiA 402 drives behind a Modbus TCP server ([drives] host, port)", true, MakeModbusTcp},
      {"cia402-shm", "the CiA 402 CSP image in shared memory on this host (an EtherCAT master process)", true,
       MakeCia402Shm},
  };
  return kinds;
}

std::string KnownBackends() {
  std::string names;
  for (const BackendKind& k : BackendKinds()) names += (names.empty() ? "" : ", ") + std::string(k.name);
  return names;
}

const BackendKind* FindBackend(const std::string& name, std::string* note) {
  note->clear();
  std::string_view wanted = name;
  for (const OldSpelling& s : kOldSpellings) {
    if (wanted == s.old_name) {
      *note = fmt::format("backend \"{}\" is now spelled \"{}\"", s.old_name, s.name);
      wanted = s.name;
    }
  }
  for (const BackendKind& k : BackendKinds()) {
    if (k.name == wanted) return &k;
  }
  note->clear();
  return nullptr;
}

ActiveBackend::ActiveBackend(const std::string& name, const BackendContext& context, const PlatformConfig& config,
                             std::string* note) {
  const BackendKind* kind = FindBackend(name, note);
  if (kind == nullptr) throw std::runtime_error("--backend " + name + ": known backends: " + KnownBackends());
  // A failure names the backend as the command line did, and its new name.
  const std::string named = note->empty() ? name : name + " (" + *note + ")";
  backend_ = kind->make(context);
  std::string error;
  if (!backend_->Configure(config, &error)) throw std::runtime_error("drive backend " + named + ": " + error);
  if (!backend_->Activate(&error)) {
    backend_->Cleanup();
    throw std::runtime_error("drive backend " + named + ": " + error);
  }
}

ActiveBackend::~ActiveBackend() {
  try {
    backend_->Deactivate();
    backend_->Cleanup();
  } catch (const std::exception& e) {  // a destructor must not throw: say it, the drives' watchdog holds them
    std::fprintf(stderr, "drive backend: deactivating: %s\n", e.what());
  }
}

}  // namespace edsp
