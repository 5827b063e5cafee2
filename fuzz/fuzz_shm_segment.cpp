// libFuzzer: a shared-memory segment as a reader finds it in /dev/shm (left
// by a dead or foreign writer, or corrupted): the header validation and the
// slot reader. The first byte steers: bit 0 repairs magic and checksum so the
// fuzzer gets past them to the geometry and slot checks.
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "edsp/transport/shm_channel.h"
#include "edsp/transport/shm_layout.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > (1u << 20)) return 0;
  const bool repair = (data[0] & 1) != 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (repair && bytes.size() >= sizeof(edsp::ShmSegmentHeader)) {
    auto* h = reinterpret_cast<edsp::ShmSegmentHeader*>(bytes.data());
    h->magic.store(edsp::kShmMagic);
    h->layout_version = edsp::kShmLayoutVersion;
    h->writer_pid.store(0);  // a dead writer: nobody else touches it meanwhile
    h->checksum = edsp::ShmHeaderChecksum(*h);
  }
  static const std::string name = "edsp.fuzz." + std::to_string(::getpid());
  const int fd = ::shm_open(name.c_str(), O_CREAT | O_RDWR | O_TRUNC, 0600);
  if (fd < 0) std::abort();
  if (!bytes.empty() && ::write(fd, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) std::abort();
  ::close(fd);
  edsp::ShmChannelSpec spec{name, 0, 2, 64, 0600};
  if (bytes.size() >= sizeof(edsp::ShmSegmentHeader)) {
    spec.type_fingerprint = reinterpret_cast<const edsp::ShmSegmentHeader*>(bytes.data())->type_fingerprint;
  }
  auto reader = edsp::ShmReader::Open(spec);
  if (reader.ok()) {
    std::uint8_t sink = 0;
    for (int k = 0; k < 64; ++k) {
      const edsp::TakeStatus status = reader.value->TryTake([&](const std::uint8_t* payload, std::uint32_t length) {
        for (std::uint32_t i = 0; i < length; ++i) sink ^= payload[i];  // every byte the reader hands out is read
        return true;
      });
      if (status == edsp::TakeStatus::kEmpty) break;
    }
    reader.value->SkipToLatest();
    (void)reader.value->Available();
    (void)sink;
  }
  ::shm_unlink(name.c_str());
  return 0;
}
