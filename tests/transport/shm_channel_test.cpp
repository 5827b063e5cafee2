// Shared-memory channel: ring protocol, overrun accounting, header checks,
// permissions, clean-up and blocking waits (single process unless noted).
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/transport/shm_channel.h"
#include "shm_test_util.h"

namespace edsp {
namespace {

using test_support::Decoded;
using test_support::DecodePattern;
using test_support::EncodePattern;
using test_support::TestSpec;

std::unique_ptr<ShmWriter> OpenWriter(const ShmChannelSpec& spec) {
  auto result = ShmWriter::Open(spec);
  EXPECT_TRUE(result.ok()) << result.message;
  return std::move(result.value);
}

std::unique_ptr<ShmReader> OpenReader(const ShmChannelSpec& spec) {
  auto result = ShmReader::Open(spec);
  EXPECT_TRUE(result.ok()) << result.message;
  return std::move(result.value);
}

std::uint64_t Publish(ShmWriter& writer, std::uint64_t number, std::uint32_t size = 64) {
  return writer.Publish(
      [&](std::uint8_t* buffer, std::uint32_t capacity) { return EncodePattern(buffer, capacity, number, 7, size); });
}

TakeStatus Take(ShmReader& reader, Decoded* out, std::uint64_t* number = nullptr) {
  return reader.TryTake([&](const std::uint8_t* data, std::uint32_t size) { return DecodePattern(data, size, out); },
                        number);
}

TEST(ShmChannel, DeliversInOrderFromTheFirstMessageAfterAttach) {
  const ShmChannelSpec spec = TestSpec("order");
  auto writer = OpenWriter(spec);
  Publish(*writer, 100);  // before the reader: not delivered to it
  auto reader = OpenReader(spec);
  for (std::uint64_t k = 1; k <= 5; ++k) EXPECT_EQ(Publish(*writer, 100 + k), k + 1);
  Decoded d;
  std::uint64_t number = 0;
  for (std::uint64_t k = 1; k <= 5; ++k) {
    ASSERT_EQ(Take(*reader, &d, &number), TakeStatus::kMessage);
    EXPECT_EQ(d.number, 100 + k);
    EXPECT_EQ(number, k + 1);
  }
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
  EXPECT_EQ(reader->stats().received, 5u);
  EXPECT_EQ(reader->stats().overruns, 0u);
}

// Found by fuzz_shm_segment: slots whose sequence runs ahead of the
// writer's own `published` count (a corrupt or foreign ring) must not make
// TryTake skip forward one message at a time, for ever: it waits.
TEST(ShmChannel, ASlotAheadOfWhatTheWriterPublishedIsNotChasedForever) {
  const ShmChannelSpec spec = TestSpec("corrupt_ring");
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  Publish(*writer, 1);
  Decoded d;
  ASSERT_EQ(Take(*reader, &d), TakeStatus::kMessage);
  // Every slot claims a message far in the future; `published` says 1.
  for (std::uint64_t n = 0; n < spec.slot_count; ++n) {
    writer->segment().slot(n)->sequence.store(std::uint64_t{1} << 62);
  }
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
  EXPECT_LE(reader->stats().overruns, 1u);
  // A `published` count near 2^64: jumping there would overflow 2·n.
  writer->segment().header()->published.store(~std::uint64_t{0} - 3);
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
}

TEST(ShmChannel, LappedReaderCountsExactlyWhatItLost) {
  const ShmChannelSpec spec = TestSpec("lap", 8);
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  for (std::uint64_t k = 1; k <= 8 + 5; ++k) Publish(*writer, k);
  Decoded d;
  std::uint64_t first = 0, count = 0;
  while (Take(*reader, &d) == TakeStatus::kMessage) {
    if (count++ == 0) first = d.number;
  }
  EXPECT_EQ(first, 6u);  // the 8 newest survive
  EXPECT_EQ(count, 8u);
  EXPECT_EQ(reader->stats().overruns, 5u);
  EXPECT_EQ(reader->stats().received + reader->stats().overruns, 13u);
}

TEST(ShmChannel, SkipToLatestIsNotAnOverrun) {
  const ShmChannelSpec spec = TestSpec("latest", 8);
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  for (std::uint64_t k = 1; k <= 5; ++k) Publish(*writer, k);
  reader->SkipToLatest();
  Decoded d;
  ASSERT_EQ(Take(*reader, &d), TakeStatus::kMessage);
  EXPECT_EQ(d.number, 5u);
  EXPECT_EQ(reader->stats().overruns, 0u);
}

// A successor reads the last state its predecessor published (the rig's
// drives after a crash), though a new reader starts after what was there.
TEST(ShmChannel, RewindToLatestReadsTheNewestMessageFromBeforeTheAttach) {
  const ShmChannelSpec spec = TestSpec("rewind", 8);
  auto writer = OpenWriter(spec);
  for (std::uint64_t k = 1; k <= 11; ++k) Publish(*writer, 40 + k);
  auto reader = OpenReader(spec);
  Decoded d;
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
  reader->RewindToLatest();
  ASSERT_EQ(Take(*reader, &d), TakeStatus::kMessage);
  EXPECT_EQ(d.number, 51u);
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
  const ShmChannelSpec silent = TestSpec("rewind_silent", 8);
  auto silent_writer = OpenWriter(silent);  // nothing published yet: nothing to rewind to
  auto silent_reader = OpenReader(silent);
  silent_reader->RewindToLatest();
  EXPECT_EQ(Take(*silent_reader, &d), TakeStatus::kEmpty);
}

TEST(ShmChannel, OversizedMessageIsNotPublished) {
  const ShmChannelSpec spec = TestSpec("oversize", 8, 64);
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  EXPECT_EQ(Publish(*writer, 1, 65), 0u);
  EXPECT_EQ(writer->published(), 0u);
  Decoded d;
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kEmpty);
  EXPECT_EQ(Publish(*writer, 2, 64), 1u);
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kMessage);
}

TEST(ShmChannel, DecodeRefusalIsCountedNotDelivered) {
  const ShmChannelSpec spec = TestSpec("decode");
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  writer->Publish([](std::uint8_t* buffer, std::uint32_t) {
    std::memset(buffer, 0, 8);
    return 8;  // too short for the pattern
  });
  Decoded d;
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kDecodeError);
  EXPECT_EQ(reader->stats().decode_errors, 1u);
  EXPECT_EQ(reader->stats().received, 0u);
}

TEST(ShmChannel, ReaderOfAnotherTypeIsRefusedByName) {
  const ShmChannelSpec spec = TestSpec("type");
  auto writer = OpenWriter(spec);
  ShmChannelSpec other = spec;
  other.type_fingerprint = 42;
  const auto reader = ShmReader::Open(other);
  EXPECT_EQ(reader.error, ShmError::kTypeMismatch);
  EXPECT_NE(reader.message.find(spec.segment_name), std::string::npos) << reader.message;
  EXPECT_NE(reader.message.find("fingerprint"), std::string::npos) << reader.message;
}

// The logger's reader copies bytes and never decodes them: it opts in to
// any type. Only a reader may: a writer always names its type, and a typed
// reader is still refused another type.
TEST(ShmChannel, OnlyAReaderThatOptsInTakesAnyTypeAndAWriterNeverMay) {
  const ShmChannelSpec spec = TestSpec("any_type");
  auto writer = OpenWriter(spec);
  ShmChannelSpec raw = spec;
  raw.type_fingerprint = 0;
  EXPECT_EQ(ShmReader::Open(raw).error, ShmError::kTypeMismatch) << "fingerprint 0 alone is no opt-in";
  raw.any_type = true;
  auto reader = OpenReader(raw);
  ASSERT_NE(reader, nullptr);
  Publish(*writer, 5);
  Decoded d;
  EXPECT_EQ(Take(*reader, &d), TakeStatus::kMessage);
  EXPECT_EQ(d.number, 5u);

  ShmChannelSpec any_writer = TestSpec("any_type_writer");
  any_writer.any_type = true;
  const auto refused = ShmWriter::Open(any_writer);
  EXPECT_EQ(refused.error, ShmError::kBadSpec);
  EXPECT_NE(refused.message.find("must name its type"), std::string::npos) << refused.message;
}

// A recorder that subscribed before the ring existed reads it from its
// first message; what the ring no longer holds is counted, not lost unseen.
TEST(ShmChannel, RewindToFirstReadsEverythingTheRingStillHoldsAndCountsTheRest) {
  const ShmChannelSpec spec = TestSpec("rewind_first", 8);
  auto writer = OpenWriter(spec);
  for (std::uint64_t n = 1; n <= 12; ++n) Publish(*writer, n);
  auto reader = OpenReader(spec);
  reader->RewindToFirst();
  Decoded d;
  std::vector<std::uint64_t> numbers;
  while (Take(*reader, &d) == TakeStatus::kMessage) numbers.push_back(d.number);
  EXPECT_EQ(numbers, (std::vector<std::uint64_t>{5, 6, 7, 8, 9, 10, 11, 12}));
  EXPECT_EQ(reader->stats().overruns, 4u);
}

TEST(ShmChannel, CorruptOrForeignHeadersAreRefused) {
  const ShmChannelSpec spec = TestSpec("corrupt");
  auto writer = OpenWriter(spec);
  ShmSegmentHeader* h = writer->segment().header();

  h->slot_count = 1024;  // geometry changed behind the checksum's back
  EXPECT_EQ(ShmReader::Open(spec).error, ShmError::kCorruptHeader);
  h->slot_count = spec.slot_count;
  ASSERT_TRUE(ShmReader::Open(spec).ok());

  h->layout_version = kShmLayoutVersion + 1;
  h->checksum = ShmHeaderChecksum(*h);
  const auto version = ShmReader::Open(spec);
  EXPECT_EQ(version.error, ShmError::kLayoutVersion);
  EXPECT_NE(version.message.find("layout version"), std::string::npos);
  h->layout_version = kShmLayoutVersion;
  h->checksum = ShmHeaderChecksum(*h);

  h->magic.store(0xdeadbeef);
  EXPECT_EQ(ShmReader::Open(spec).error, ShmError::kCorruptHeader);
  h->magic.store(0);
  EXPECT_EQ(ShmReader::Open(spec).error, ShmError::kNotReady);
  h->magic.store(kShmMagic);
  EXPECT_TRUE(ShmReader::Open(spec).ok());
}

TEST(ShmChannel, ReaderBeforeWriterIsNotFound) {
  const auto reader = ShmReader::Open(TestSpec("absent"));
  EXPECT_EQ(reader.error, ShmError::kNotFound);
}

TEST(ShmChannel, BadSpecsAreRefused) {
  EXPECT_EQ(ShmWriter::Open(TestSpec("slots", 6)).error, ShmError::kBadSpec);
  EXPECT_EQ(ShmWriter::Open(TestSpec("size", 8, 0)).error, ShmError::kBadSpec);
  ShmChannelSpec slash = TestSpec("slash");
  slash.segment_name = "a/b";
  EXPECT_EQ(ShmWriter::Open(slash).error, ShmError::kBadSpec);
}

mode_t SegmentMode(const std::string& name) {
  struct stat st {};
  if (::stat(("/dev/shm/" + name).c_str(), &st) != 0) return 0;
  return st.st_mode & 0777;
}

TEST(ShmChannel, PermissionsAreAsConfiguredAndOrderlyExitRemovesTheSegment) {
  ShmChannelSpec spec = TestSpec("mode");
  {
    auto writer = OpenWriter(spec);
    EXPECT_EQ(SegmentMode(spec.segment_name), 0600u);
  }
  EXPECT_EQ(SegmentMode(spec.segment_name), 0u) << "segment left behind";
  spec.permissions = 0660;
  auto writer = OpenWriter(spec);
  EXPECT_EQ(SegmentMode(spec.segment_name), 0660u);
}

TEST(ShmChannel, SecondLiveWriterIsRefused) {
  const ShmChannelSpec spec = TestSpec("two-writers");
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = test_support::Spawn([&] {
    auto writer = ShmWriter::Open(spec);
    const char byte = writer.ok() ? 'y' : 'n';
    (void)!::write(ready[1], &byte, 1);
    ::pause();
    return 0;
  });
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ASSERT_EQ(byte, 'y');
  const auto second = ShmWriter::Open(spec);
  EXPECT_EQ(second.error, ShmError::kWriterAlive);
  EXPECT_NE(second.message.find(std::to_string(child)), std::string::npos) << second.message;
  ::kill(child, SIGKILL);
  test_support::WaitExit(child);
  // Its writer is dead now: the segment is taken over, not refused.
  EXPECT_TRUE(ShmWriter::Open(spec).ok());
}

TEST(ShmChannel, StaleSegmentOfADeadWriterIsReclaimedEvenIfIncompatible) {
  const ShmChannelSpec old_spec = TestSpec("stale");
  const pid_t child = test_support::Spawn([&] {
    auto writer = ShmWriter::Open(old_spec);
    Publish(*writer.value, 1);
    ::kill(::getpid(), SIGKILL);  // dies without cleaning up
    return 0;
  });
  EXPECT_EQ(test_support::WaitExit(child), 128 + SIGKILL);
  EXPECT_EQ(SegmentMode(old_spec.segment_name), 0600u) << "the crash should leave it behind";
  ShmChannelSpec new_spec = old_spec;
  new_spec.type_fingerprint = 99;
  new_spec.slot_count = 16;
  auto writer = OpenWriter(new_spec);
  ASSERT_NE(writer, nullptr);
  EXPECT_EQ(writer->segment().header()->slot_count, 16u);
  EXPECT_EQ(writer->published(), 0u);
}

TEST(ShmChannel, WaitTimesOutWhenIdleAndWakesOnPublish) {
  const ShmChannelSpec spec = TestSpec("wait");
  auto writer = OpenWriter(spec);
  auto reader = OpenReader(spec);
  EXPECT_FALSE(reader->Wait(std::chrono::milliseconds(20)));
  std::thread publisher([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    Publish(*writer, 1);
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(reader->Wait(std::chrono::seconds(5)));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(4));
  publisher.join();
  EXPECT_EQ(writer->segment().header()->sleepers.load(), 0u);
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

double ThreadCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
}

TEST(ShmChannel, IdleWaitingReaderSleepsInsteadOfSpinning) {
  const ShmChannelSpec spec = test_support::TestSpec("idle");
  auto writer = ShmWriter::Open(spec);
  ASSERT_TRUE(writer.ok());
  auto reader = ShmReader::Open(spec);
  ASSERT_TRUE(reader.ok());
  const double before = ThreadCpuSeconds();
  EXPECT_FALSE(reader.value->Wait(std::chrono::milliseconds(300)));  // default: spin, then sleep
  // A spinning reader would burn ~0.3 s of CPU here; a sleeping one almost none.
  EXPECT_LT(ThreadCpuSeconds() - before, 0.05);
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

// One thread sleeping on several channels (futex_waitv): it sleeps while all
// are idle, wakes on a message on any of them, and leaves no sleeper behind.
TEST(ShmChannel, WaitAnySleepsOnEveryChannelAndWakesOnTheOneThatIsWritten) {
  std::vector<std::unique_ptr<ShmWriter>> writers;
  std::vector<std::unique_ptr<ShmReader>> readers;
  std::vector<ShmReader*> raw;
  for (int i = 0; i < 3; ++i) {
    const ShmChannelSpec spec = test_support::TestSpec("any" + std::to_string(i));
    writers.push_back(OpenWriter(spec));
    readers.push_back(OpenReader(spec));
    raw.push_back(readers.back().get());
  }
  const double before = ThreadCpuSeconds();
  EXPECT_FALSE(ShmReader::WaitAny(raw.data(), 3, std::chrono::milliseconds(300)));
  EXPECT_LT(ThreadCpuSeconds() - before, 0.05);  // slept, did not spin
  for (int target = 0; target < 3; ++target) {
    std::thread publisher([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      Publish(*writers[static_cast<std::size_t>(target)], 1 + static_cast<std::uint64_t>(target));
    });
    const auto start = std::chrono::steady_clock::now();
    EXPECT_TRUE(ShmReader::WaitAny(raw.data(), 3, std::chrono::seconds(5)));
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(4)) << target;
    publisher.join();
    EXPECT_TRUE(raw[static_cast<std::size_t>(target)]->Available());
    for (auto& w : writers) EXPECT_EQ(w->segment().header()->sleepers.load(), 0u);
    raw[static_cast<std::size_t>(target)]->SkipToLatest();
  }
}

}  // namespace
}  // namespace edsp
