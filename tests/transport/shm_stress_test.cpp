// Multi-process tests of the shared-memory channel and the bus (ctest label
// `multiprocess`): a million messages past a slow reader, a writer killed and
// restarted mid-stream, and shm vs LCM-mirror readers seeing one sequence.
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>

#include <atomic>
#include <new>

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/bus.h"
#include "shm_test_util.h"

namespace edsp {
namespace {

using namespace std::chrono_literals;
using test_support::Decoded;
using test_support::DecodePattern;
using test_support::EncodePattern;

// A one-way channel between processes (one per direction: a process that
// writes and then reads the same pipe reads its own message back). Receive
// gives up after 30 s so a dead peer fails the test instead of hanging it.
class Pipe {
 public:
  Pipe() { EXPECT_EQ(::pipe(fds_), 0); }
  ~Pipe() {
    ::close(fds_[0]);
    ::close(fds_[1]);
  }
  void Send(std::uint64_t value) { (void)!::write(fds_[1], &value, sizeof value); }
  bool Ready() {
    pollfd fd{fds_[0], POLLIN, 0};
    return ::poll(&fd, 1, 0) == 1;
  }
  std::uint64_t Receive() {
    pollfd fd{fds_[0], POLLIN, 0};
    if (::poll(&fd, 1, 30000) != 1) return ~0ull;
    std::uint64_t value = 0;
    return ::read(fds_[0], &value, sizeof value) == sizeof value ? value : ~0ull;
  }
  template <typename T>
  void SendVector(const std::vector<T>& v) {
    Send(v.size());
    (void)!::write(fds_[1], v.data(), v.size() * sizeof(T));
  }
  template <typename T>
  std::vector<T> ReceiveVector() {
    const std::uint64_t count = Receive();
    if (count == ~0ull) return {};
    std::vector<T> v(count);
    std::size_t got = 0;
    auto* bytes = reinterpret_cast<char*>(v.data());
    while (got < v.size() * sizeof(T)) {
      const ssize_t n = ::read(fds_[0], bytes + got, v.size() * sizeof(T) - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    return v;
  }

 private:
  int fds_[2];
};

std::unique_ptr<ShmReader> OpenReaderWhenReady(const ShmChannelSpec& spec) {
  for (int k = 0; k < 2000; ++k) {
    auto reader = ShmReader::Open(spec);
    if (reader.ok()) return std::move(reader.value);
    std::this_thread::sleep_for(1ms);
  }
  ADD_FAILURE() << "no segment " << spec.segment_name;
  return nullptr;
}

void BusyWait(std::chrono::nanoseconds duration) {
  const auto until = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < until) {
  }
}

TEST(ShmStress, MillionMessagesPastASlowReaderNoTornReadEveryLossCounted) {
  // At least a million messages; more if the reader (starved on a loaded
  // machine) has not yet taken kEnough of them, so the torn-read check always
  // runs on a large sample whatever the load.
  constexpr std::uint64_t kMessages = 1000000, kEnough = 20000;
  const ShmChannelSpec spec = test_support::TestSpec("million", 64, 512);
  auto* enough = static_cast<std::atomic<bool>*>(
      ::mmap(nullptr, sizeof(std::atomic<bool>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(enough, MAP_FAILED);
  new (enough) std::atomic<bool>(false);
  Pipe writer_ready, reader_ready, writer_done, reader_done;
  const pid_t writer = test_support::Spawn([&] {
    auto w = ShmWriter::Open(spec);
    if (!w.ok()) return 2;
    writer_ready.Send(1);
    reader_ready.Receive();
    for (std::uint64_t k = 1; k <= kMessages || !enough->load(std::memory_order_relaxed); ++k) {
      const std::uint32_t size = 16 + static_cast<std::uint32_t>(k % 497);
      w.value->Publish(
          [&](std::uint8_t* buffer, std::uint32_t capacity) { return EncodePattern(buffer, capacity, k, 1, size); });
    }
    writer_done.Send(w.value->published());
    reader_done.Receive();  // keep the segment until the reader has drained
    return 0;
  });
  ASSERT_EQ(writer_ready.Receive(), 1u);
  auto reader = OpenReaderWhenReady(spec);
  ASSERT_NE(reader, nullptr);
  reader_ready.Send(1);

  std::uint64_t accepted_torn = 0, out_of_order = 0, last = 0, received = 0;
  std::uint64_t published = ~0ull;  // known once the writer says so
  for (;;) {
    Decoded d;
    std::uint64_t number = 0;
    const TakeStatus status = reader->TryTake(
        [&](const std::uint8_t* data, std::uint32_t size) { return DecodePattern(data, size, &d); }, &number);
    if (status == TakeStatus::kMessage) {
      ++received;
      if (!d.intact || d.number != number) ++accepted_torn;
      if (number <= last) ++out_of_order;
      last = number;
      if (received == kEnough) enough->store(true);
      if (received % 64 == 0) BusyWait(20us);  // deliberately slow
      continue;
    }
    ASSERT_NE(status, TakeStatus::kDecodeError) << "a torn slot was handed over as a message";
    if (published == ~0ull && writer_done.Ready()) published = writer_done.Receive();
    if (reader->next_message() > published) break;  // every number read or counted lost
  }
  reader_done.Send(1);
  EXPECT_EQ(test_support::WaitExit(writer), 0);
  ::munmap(enough, sizeof(std::atomic<bool>));
  const ShmReaderStats& s = reader->stats();
  EXPECT_GE(published, kMessages);
  EXPECT_EQ(accepted_torn, 0u);
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(s.received, received);
  EXPECT_EQ(s.received + s.overruns, published) << "every message is either read or counted lost";
  EXPECT_GT(s.overruns, 0u) << "the reader was meant to be too slow";
  EXPECT_GE(s.received, kEnough);
  ::testing::Test::RecordProperty("published", static_cast<int>(published));
  ::testing::Test::RecordProperty("received", static_cast<int>(s.received));
  ::testing::Test::RecordProperty("overruns", static_cast<int>(s.overruns));
  ::testing::Test::RecordProperty("torn_detected", static_cast<int>(s.torn));
}

TEST(ShmStress, WriterKilledAndRestartedMidStreamReadersCarryOn) {
  const ShmChannelSpec spec = test_support::TestSpec("restart", 64, 256);
  auto publish_forever = [&](std::uint32_t tag, std::uint64_t limit) {
    return [&spec, tag, limit] {
      auto w = ShmWriter::Open(spec);
      if (!w.ok()) return 2;
      for (std::uint64_t k = 1; k <= limit; ++k) {
        w.value->Publish(
            [&](std::uint8_t* buffer, std::uint32_t capacity) { return EncodePattern(buffer, capacity, k, tag, 64); });
        std::this_thread::sleep_for(20us);
      }
      ::pause();
      return 0;
    };
  };
  const pid_t first = test_support::Spawn(publish_forever(1, ~0ull));
  auto reader = OpenReaderWhenReady(spec);
  ASSERT_NE(reader, nullptr);
  const std::uint32_t generation = reader->writer_generation();

  std::uint64_t last_number = 0, from_first = 0, from_second = 0, out_of_order = 0;
  auto read_until = [&](auto done, std::chrono::seconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done() && std::chrono::steady_clock::now() < deadline) {
      if (!reader->Wait(100ms)) continue;
      Decoded d;
      std::uint64_t number = 0;
      while (reader->TryTake([&](const std::uint8_t* p, std::uint32_t n) { return DecodePattern(p, n, &d); },
                             &number) == TakeStatus::kMessage) {
        if (number <= last_number) ++out_of_order;
        last_number = number;
        (d.tag == 1 ? from_first : from_second) += 1;
      }
    }
  };
  read_until([&] { return from_first >= 500; }, 20s);
  ASSERT_GE(from_first, 500u);
  ::kill(first, SIGKILL);  // mid-stream, possibly mid-slot
  EXPECT_EQ(test_support::WaitExit(first), 128 + SIGKILL);
  EXPECT_FALSE(reader->WriterAlive());

  const pid_t second = test_support::Spawn(publish_forever(2, 2000));
  read_until([&] { return from_second >= 1000; }, 20s);  // same reader, never reopened
  EXPECT_GE(from_second, 1000u);
  EXPECT_EQ(out_of_order, 0u) << "message numbers continue across the restart";
  EXPECT_TRUE(reader->WriterAlive());
  EXPECT_EQ(reader->writer_generation(), generation + 1);
  ::kill(second, SIGKILL);
  test_support::WaitExit(second);
  RemoveSegment(spec.segment_name);
}

TransportConfig BothConfig(const std::string& prefix) {
  TransportConfig config;
  config.shm_prefix = prefix;
  ChannelRoute route;
  route.path = ChannelPath::kBoth;
  route.slots = 4096;  // deep enough that the shm reader loses nothing
  route.slot_size_bytes = 512;
  config.channels["EDSP_SETPOINT"] = route;
  return config;
}

TEST(BusMultiprocess, ShmReaderAndLcmMirrorReaderSeeTheSameSequence) {
  constexpr int kMessages = 3000;
  const std::string prefix = "edsp.mirror." + std::to_string(::getpid());
  Pipe created, shm_ready, lcm_ready, shm_result, lcm_result, go;
  auto reader = [&](bool via_shm, Pipe* ready, Pipe* result) {
    return [&, via_shm, ready, result] {
      // A process on another host would have no shm route: plain LCM.
      Bus bus(via_shm ? BothConfig(prefix) : TransportConfig{});
      std::vector<std::int64_t> seqs;
      bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& m) { seqs.push_back(m.seq); });
      ready->Send(1);
      const auto deadline = std::chrono::steady_clock::now() + 20s;
      while (static_cast<int>(seqs.size()) < kMessages && std::chrono::steady_clock::now() < deadline) {
        bus.Handle(10ms);
      }
      result->SendVector(seqs);
      return 0;
    };
  };
  const pid_t publisher = test_support::Spawn([&] {
    Bus bus(BothConfig(prefix));
    auto out = bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
    created.Send(1);
    go.Receive();
    for (int k = 1; k <= kMessages; ++k) {
      pose_setpoint_t m{};
      m.seq = k;
      m.trajectory = "mirror";
      out.Publish(m);
      // 2 kHz: the LCM reader's 4 MiB socket buffer then holds over a
      // second of this stream, so a reader descheduled on a busy machine
      // catches up instead of losing datagrams (its throughput is the
      // transport benchmark's business, not this test's).
      std::this_thread::sleep_for(500us);
    }
    go.Receive();  // keep the segment until both readers are done
    return 0;
  });
  // The segment exists before the readers subscribe, so the shm reader
  // attaches as it subscribes (no attach retry to wait for).
  ASSERT_EQ(created.Receive(), 1u) << "the publisher never made its segment";
  const pid_t shm_reader = test_support::Spawn(reader(true, &shm_ready, &shm_result));
  const pid_t lcm_reader = test_support::Spawn(reader(false, &lcm_ready, &lcm_result));
  shm_ready.Receive();
  lcm_ready.Receive();
  go.Send(1);
  const auto via_shm = shm_result.ReceiveVector<std::int64_t>();
  const auto via_lcm = lcm_result.ReceiveVector<std::int64_t>();
  go.Send(1);
  EXPECT_EQ(test_support::WaitExit(shm_reader), 0);
  EXPECT_EQ(test_support::WaitExit(lcm_reader), 0);
  EXPECT_EQ(test_support::WaitExit(publisher), 0);
  std::vector<std::int64_t> expected(kMessages);
  for (int k = 0; k < kMessages; ++k) expected[static_cast<std::size_t>(k)] = k + 1;
  EXPECT_EQ(via_shm, expected) << via_shm.size() << " of " << kMessages << " via shm";
  EXPECT_EQ(via_lcm, expected) << via_lcm.size() << " of " << kMessages << " via LCM";
}

}  // namespace
}  // namespace edsp
