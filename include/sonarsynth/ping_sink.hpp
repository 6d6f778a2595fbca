// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>

#include "sonarsynth/rendered_ping.hpp"
#include "sonarsynth/simulation_config.hpp"

/// The receiving end of Simulator::run: a run description, then pings in survey order.
namespace sonarsynth {

/// What a sink is told before the first ping of a run (Simulator::run).
struct RunDescription {
  SimulationConfig config;         ///< the configuration the pings are rendered with
  double gain_db = 0.0;            ///< the quantiser gain actually applied (automatic resolved), dB
  double absorption_db_per_m = 0;  ///< one-way absorption alpha used by physics and TVG, dB/m
  std::uint64_t total_pings = 0;   ///< pings that will be handed to ping()
  std::size_t line_count = 0;      ///< survey lines
};

/// Receives rendered pings in survey order, one at a time (streaming: memory does not grow with
/// survey length). Simulator::run calls, in order: begin() once; per line begin_line(), ping()
/// for each of its pings, end_line(); finish() once after the last line. If anything throws
/// (rendering, a sink, a progress callback) it calls abort() instead of the remaining hooks and
/// rethrows: a sink then discards partial output. Every hook is a no-op by default.
class PingSink {
 public:
  virtual ~PingSink() = default;
  virtual void begin(const RunDescription& /*run*/) {}
  virtual void begin_line(std::size_t /*line*/) {}
  virtual void ping(const RenderedPing& /*ping*/) {}
  virtual void end_line(std::size_t /*line*/) {}
  virtual void finish() {}
  /// The run failed: release resources and leave no partial files. Must not throw.
  virtual void abort() noexcept {}
};

}  // namespace sonarsynth
