// Periodic state hashes in recordings (engine/realtime/recording.h `h` lines, HashVerifier): a
// threaded live run writes the full state hash every hash_every ticks; replaying checks each one;
// a tampered recording (one command's value changed, or one recorded hash) is caught at the first
// hash tick after the change, named by file, line and tick. Crash safety: a process that dies
// mid-run (no destructor, no finish) leaves FILE.part with every command and hash written up to
// about one flush period before it died, and it parses and replays.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/recording.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

std::string temp_dir() {
  const auto d = std::filesystem::temp_directory_path() /
                 ("ps_rech_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(d);
  return d.string();
}

std::string dir_of(const std::string& path) { return std::filesystem::path(path).parent_path().string(); }

constexpr int kEvery = 50;
constexpr int64_t kTicks = 400;

// A threaded live run of the live_box script, recorded with hashes every kEvery ticks.
std::string record_live(const std::string& dir) {
  const std::string path = dir + "/live.rec";
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer p(script_commands(s, sc));
  RecordingHeader h{sc.spec.name, sc.content_hash, sc.model->dt, sc.model->substeps};
  h.hash_every = kEvery;
  RecordingWriter rec(path, h);
  LoopOptions opt;
  opt.stop_at_tick = kTicks;
  opt.log_timing = false;
  opt.as_fast_as_possible = true;
  PhysicsLoop loop(*sc.sim, opt);
  loop.add_source(&p);
  loop.applier().set_observer(&rec);
  loop.set_hash_observer(&rec, rec.hash_every());
  loop.start();
  loop.wait_for_tick(kTicks);
  loop.stop();
  rec.finish(loop.tick(), sc.sim->hash());
  EXPECT_EQ(rec.dropped(), 0);
  return path;
}

struct Check {
  int checked = 0;
  bool diverged = false;
  int64_t tick = -1;
  std::string text;
};

Check replay(const Recording& r) {
  Scene sc = test::make_live_scene();
  CommandPlayer p(r.commands);
  LockstepRunner run(*sc.sim);
  run.add_source(&p);
  HashVerifier v(r);
  run.runner().set_hash_observer(&v, r.header.hash_every);
  EXPECT_TRUE(run.advance_to(r.complete ? r.end_tick : kTicks));
  return {v.checked(), v.diverged(), v.diverged_tick(), v.describe()};
}

// TickRunner::spread_hashes (the real-time loop's way): the same hashes for the same ticks as
// hashing at the tick, each handed over within hash_every / 2 ticks of its own, without allocating
TEST(RecordingHashes, SpreadOverTicksTheyAreTheSameHashesForTheSameTicks) {
  struct Log final : HashObserver {
    LockstepRunner* run = nullptr;
    std::vector<std::pair<int64_t, uint64_t>> got;
    std::vector<int64_t> at;  // ticks completed when each was handed over
    void state_hash(int64_t ticks, uint64_t hash) override {
      got.emplace_back(ticks, hash);
      at.push_back(run->tick());
    }
  };
  Log plain, spread;
  long allocations = -1;
  for (Log* log : {&plain, &spread}) {
    Scene sc = test::make_live_scene();
    const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
    CommandPlayer p(script_commands(s, sc));
    LockstepRunner run(*sc.sim);
    log->run = &run;
    log->got.reserve(64);
    log->at.reserve(64);
    run.add_source(&p);
    run.runner().set_hash_observer(log, kEvery);
    if (log == &spread) run.runner().spread_hashes(true);
    ASSERT_TRUE(run.advance_to(kEvery + 1));  // past the first save into the buffers
    const long before = test::allocation_count();
    ASSERT_TRUE(run.advance_to(kTicks));
    if (log == &spread) allocations = test::allocation_count() - before;
    run.runner().finish_hashes();
  }
  ASSERT_EQ(plain.got.size(), static_cast<size_t>(kTicks / kEvery));
  EXPECT_EQ(spread.got, plain.got);
  for (size_t i = 0; i < spread.got.size(); ++i) {
    EXPECT_EQ(plain.at[i], plain.got[i].first);  // at its tick
    if (i + 1 < spread.got.size()) {              // the last one by finish_hashes()
      EXPECT_GT(spread.at[i], spread.got[i].first);
      EXPECT_LE(spread.at[i], spread.got[i].first + kEvery / 2);
    }
  }
  EXPECT_EQ(allocations, 0);
}

TEST(RecordingHashes, LiveRunWritesThemAndReplayChecksEveryOne) {
  const std::string path = record_live(temp_dir());
  const Recording r = parse_recording_file(path);
  EXPECT_EQ(r.header.hash_every, kEvery);
  ASSERT_EQ(r.hashes.size(), static_cast<size_t>(kTicks / kEvery));
  for (size_t i = 0; i < r.hashes.size(); ++i) EXPECT_EQ(r.hashes[i].tick, static_cast<int64_t>((i + 1) * kEvery));
  EXPECT_EQ(r.hashes.back().hash, r.end_hash);  // the last h line is the end state
  const Check c = replay(r);
  EXPECT_EQ(c.checked, kTicks / kEvery);
  EXPECT_FALSE(c.diverged) << c.text;
}

TEST(RecordingHashes, ATamperedCommandIsCaughtAtTheNextHashWithFileLineAndTick) {
  const std::string path = record_live(temp_dir());
  const Recording r = parse_recording_file(path);
  // change the value of the command applied at tick 250 (needle gun to 22 mm at some speed):
  // the replay departs from the live run at that tick, so the h line of tick 250 (taken before
  // the command) still matches and the one of tick 300 is the first that differs
  std::string text = test::read_text(path);
  const std::regex line("\nc 250 needle_aim [^\n]*");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, line)) << text;
  std::string changed = m.str();
  const auto sp = changed.rfind(' ');  // the last field: dir z of the aim
  changed = changed.substr(0, sp) + " 0.001";
  const std::string tampered = dir_of(path) + "/tampered.rec";
  std::ofstream(tampered) << text.substr(0, m.position()) + changed + text.substr(m.position() + m.length());
  const Recording t = parse_recording_file(tampered);
  const Check c = replay(t);
  EXPECT_TRUE(c.diverged);
  EXPECT_EQ(c.tick, 300);
  int hline = 0;
  for (const RecordedHash& h : t.hashes)
    if (h.tick == 300) hline = h.line;
  EXPECT_NE(c.text.find(tampered + ":" + std::to_string(hline) + ": tick 300:"), std::string::npos) << c.text;
  EXPECT_NE(c.text.find("between tick 250 and this one"), std::string::npos) << c.text;
}

TEST(RecordingHashes, ATamperedHashIsCaughtAtItsTick) {
  const std::string path = record_live(temp_dir());
  std::string text = test::read_text(path);
  const auto p = text.find("\nh 150 ");
  ASSERT_NE(p, std::string::npos);
  char& digit = text[p + 7];
  digit = digit == '0' ? '1' : '0';
  const std::string tampered = dir_of(path) + "/tampered_hash.rec";
  std::ofstream(tampered) << text;
  const Check c = replay(parse_recording_file(tampered));
  EXPECT_TRUE(c.diverged);
  EXPECT_EQ(c.tick, 150);
}

TEST(RecordingHashes, HashLinesOutOfOrderOrOffTheGridAreBadInput) {
  const std::string head = "prostatesim-recording 2\nprogram 0.1\nscenario x\nscenario_hash 0000000000000001\ndt 0.001\nsubsteps 1\nhash_every 50\n";
  EXPECT_THROW(parse_recording_text(head + "h 100 0000000000000001\nh 50 0000000000000002\n", "r.rec"), InputError);
  EXPECT_THROW(parse_recording_text(head + "h 75 0000000000000001\n", "r.rec"), InputError);
  EXPECT_THROW(parse_recording_text(head + "h 100 xyz\n", "r.rec"), InputError);
  EXPECT_THROW(parse_recording_text(head + "h 100 0000000000000001\nend 50 0000000000000001\n", "r.rec"), InputError);
  try {
    parse_recording_text(head + "h 100 0000000000000001\nh 50 0000000000000002\n", "r.rec");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r.rec:9:"), std::string::npos) << e.what();
  }
  // version 1 recordings (no hashes) still read
  const Recording v1 = parse_recording_text("prostatesim-recording 1\nprogram 0.1\nscenario x\nscenario_hash 0000000000000001\ndt 0.001\nsubsteps 1\nend 5 0000000000000001\n", "v1.rec");
  EXPECT_EQ(v1.header.hash_every, 0);
  EXPECT_TRUE(v1.complete);
}

// The child of the crash test: records a live run, then dies without any cleanup.
[[noreturn]] void crash_while_recording(const std::string& path) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer p(script_commands(s, sc));
  RecordingHeader h{sc.spec.name, sc.content_hash, sc.model->dt, sc.model->substeps};
  h.hash_every = kEvery;
  auto* rec = new RecordingWriter(path, h);  // never deleted: the crash
  LoopOptions o;
  o.stop_at_tick = kTicks;
  o.log_timing = false;
  o.as_fast_as_possible = true;
  auto* loop = new PhysicsLoop(*sc.sim, o);
  loop->add_source(&p);
  loop->applier().set_observer(rec);
  loop->set_hash_observer(rec, rec->hash_every());
  loop->start();
  loop->wait_for_tick(kTicks);
  // the physics is done; wait past two flush periods, then die without any cleanup
  std::this_thread::sleep_for(std::chrono::duration<double>(2.5 * kFlushSeconds));
  _exit(7);
}

// The writer's process dies (no destructor, no finish, no atexit) a while into a run: FILE.part
// keeps what was flushed, parses, and replays to the same hashes.
TEST(RecordingHashes, ACrashKeepsTheSessionUpToTheLastFlush) {
  // no pid in the name: the child of a "threadsafe" death test is a new process
  const auto dir = std::filesystem::temp_directory_path() / "ps_rech_crash";
  const std::string path = (dir / "crash.rec").string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_EXIT(crash_while_recording(path), ::testing::ExitedWithCode(7), "");
  EXPECT_FALSE(std::filesystem::exists(path));
  ASSERT_TRUE(std::filesystem::exists(path + ".part"));
  const Recording r = parse_recording_file(path + ".part");
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(r.commands.size(), 10u);  // every script entry before tick 400 (the one at 400 never ran)
  EXPECT_EQ(r.hashes.size(), static_cast<size_t>(kTicks / kEvery));
  const Check c = replay(r);
  EXPECT_EQ(c.checked, kTicks / kEvery);
  EXPECT_FALSE(c.diverged) << c.text;
}

}  // namespace
}  // namespace ps
