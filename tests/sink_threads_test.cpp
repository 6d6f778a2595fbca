// SPDX-License-Identifier: MIT
// The sinks run on threads of their own
// (formats/private/sonarsynth/formats/products/sink_threads.hpp): each receives every call in order
// with the ping as it was when queued, and a sink's failure reaches the producing side.
#include "sonarsynth/formats/products/sink_threads.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

/// Records every call; throws FormatError at ping number `fail_at` (if set).
class RecordingSink : public PingSink {
 public:
  explicit RecordingSink(int fail_at = -1) : fail_at_(fail_at) {}
  void begin(const RunDescription& run) override {
    log.push_back("begin " + std::to_string(run.total_pings));
  }
  void begin_line(std::size_t line) override { log.push_back("line " + std::to_string(line)); }
  void ping(const RenderedPing& p) override {
    if (pings++ == fail_at_) throw FormatError("recording sink: disk full");
    std::ostringstream s;
    s << "ping " << p.pose.ping_in_line;
    for (float v : p.port.samples) s << " " << v;
    for (std::int32_t id : p.starboard.truth_label) s << " id" << id;
    log.push_back(s.str());
  }
  void end_line(std::size_t line) override { log.push_back("end " + std::to_string(line)); }
  void finish() override { log.push_back("finish"); }
  void abort() noexcept override { log.push_back("abort"); }
  std::vector<std::string> log;

 private:
  int fail_at_;
  int pings = 0;
};

/// Feeds `lines` lines of `per_line` pings, reusing one ping object as the Simulator does.
void feed(PingSink& sink, std::size_t lines, std::size_t per_line) {
  RunDescription run;
  run.total_pings = lines * per_line;
  sink.begin(run);
  RenderedPing p;
  for (std::size_t l = 0; l < lines; ++l) {
    sink.begin_line(l);
    for (std::size_t i = 0; i < per_line; ++i) {
      p.pose.ping_in_line = i;
      p.port.samples.assign(3, static_cast<float>(100 * l + i));
      p.starboard.truth_label.assign(1, static_cast<std::int32_t>(l));
      sink.ping(p);
    }
    sink.end_line(l);
  }
  sink.finish();
}

TEST(ParallelSink, EverySinkReceivesEveryCallInOrderWithThePingAsQueued) {
  RecordingSink expected, inline_sink, a, b;
  feed(expected, 3, 50);
  // A queue of 2 pings: the producer overwrites its ping long before the threads read theirs.
  detail::ParallelSink sink({&inline_sink}, {{&a, "a"}, {&b, "b"}}, 2);
  feed(sink, 3, 50);
  EXPECT_EQ(inline_sink.log, expected.log);
  EXPECT_EQ(a.log, expected.log);
  EXPECT_EQ(b.log, expected.log);
  const auto cpu = sink.thread_cpu_s();
  ASSERT_EQ(cpu.size(), 2U);
  EXPECT_EQ(cpu[0].first, "a");
  EXPECT_EQ(cpu[1].first, "b");
}

TEST(ParallelSink, AFailingThreadedSinkFailsTheProducerWithItsErrorAndAbortStopsAll) {
  RecordingSink good, bad(17), inline_sink;
  detail::ParallelSink sink({&inline_sink}, {{&good, "good"}, {&bad, "bad"}}, 4);
  std::string message;
  try {
    feed(sink, 2, 100);
  } catch (const FormatError& e) {
    message = e.what();
  }
  EXPECT_EQ(message, "recording sink: disk full");
  sink.abort();  // what Simulator::run does on an exception
  for (const RecordingSink* s : {&good, &bad, &inline_sink}) {
    ASSERT_FALSE(s->log.empty());
    EXPECT_EQ(s->log.back(), "abort");
    EXPECT_EQ(std::find(s->log.begin(), s->log.end(), "finish"), s->log.end());
  }
  // The failing sink received nothing after its failure.
  EXPECT_EQ(bad.log.size(), 1U + 1U + 17U + 1U);  // begin, line 0, 17 pings, abort
}

TEST(BackgroundJob, RunsOneJobAtATimeAndRethrowsItsError) {
  detail::BackgroundJob job;
  int done = 0;
  job.run([&] { ++done; });
  job.run([&] { ++done; });  // waits for the first
  job.wait();
  EXPECT_EQ(done, 2);
  job.run([] { throw FormatError("image: cannot write"); });
  EXPECT_THROW(job.wait(), FormatError);
  job.wait();  // the error is reported once
}

}  // namespace
}  // namespace sonarsynth
