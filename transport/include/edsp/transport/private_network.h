#pragma once
// For tests and benchmarks that use LCM multicast: moves the calling process
// (and every child it forks afterwards) into a fresh network namespace with
// loopback up and 224.0.0.0/4 routed over it, so no packet can leave the
// machine. Call it while the process is still single-threaded.

namespace edsp {

// Throws TransportError saying what failed (root, or unprivileged user
// namespaces, are needed; `ip` from iproute2).
void EnterPrivateNetworkNamespace();

}  // namespace edsp
