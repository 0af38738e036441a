// SPDX-License-Identifier: MIT
// navd's event loop: one thread, one Boost.Asio io_context, non-blocking ports.
//
//   bench/devices ──AHRS 0xCB──▶ [ahrs tty]  ─┐  one async_wait each; the handler only
//                 ──NMEA GGA/RMC▶ [gps tty]  ─┤  marks what is ready
//                 ──DVL/USBL/..─▶ [--input]  ─┤
//   Keller (polled) ◀─requests─▶ [--input]   ─┤
//   other vehicles ◀─$PNVBPOS──▶ [--modem]   ─┼─ io.run_one(); io.poll() ─▶ wake (every
//                  (p2: state reports)        │
//   N2K, wheel encoders ─frames─▶ [--can]    ─┤  handler ready then has run):
//   SIGTERM/SIGINT ────────────▶ [signal_set]─┤ 1. read every serial port until EAGAIN,
//   hang-up, room for output ──▶ [output]    ─┘    marked ready or not (a pty's bytes may
//                                                  not be marked yet), the trigger port
//                                                  (AHRS, or the P3/P4 trigger input) first,
//                                                  then GPS, then the other --input ports
//                                                  in command-line order, then the CAN
//                                                  socket (marked or not), then the modem;
//                                                  feed each port's stream decoder
//                                                  (--input messages, CAN frames and peer
//                                                  reports are counted and the last one
//                                                  kept as they are decoded)
//                                               2. every decoded GPS sentence → fix queue
//                                                  (gps-ins navigator), then every Keller
//                                                  answer → its poller → depth queue, then
//                                                  the last DVL velocity of each DVL input
//                                                  → dead reckoning (dvl, p2 navigators),
//                                                  then (p2) every iUSBL fix, then every
//                                                  state report heard
//                                               3. every decoded 0xCB packet, in arrival
//                                                  order: Keller requests due at its timer
//                                                  → [keller tty], navigator step
//                                                  (attitude, predict, queued fixes and
//                                                  depths), the $PNVBPOS due at its timer
//                                                  → [modem tty], (--delay-ms: a
//                                                  steady_timer), one $PNVBSOL
//                                               4. output queue → [output tty] (never blocks)
//                                               5. arm the waits of the ports read (and of
//                                                  the output while sentences wait)
//
// The P3 navigators (p3-dr, p3-ekf, p3-ekf-kr, navd_p3.cpp) run without an AHRS port: their
// trigger is the first --input of protocol ebimu. In step 2 the wheel encoder samples decoded
// from CAN go to the navigator (other navigators drop them); in step 3 each EBIMU line of
// p3_ebimu_values values, in arrival order, writes the Keller requests due at the P3 clock
// (lines stepped / p3_ebimu_rate_hz), steps the navigator and writes one $PNVBSOL whose
// trigger_tag is the line's ordinal (the LF bytes before it on that port).
//
// The P4 navigators (p4-ukf, p4-dwt-ukf, navd_p4.cpp) run without an AHRS port too: their
// trigger is the first --input of protocol beacon-ins. In step 2 every RMC of the GPS port
// (position, and speed/course when present) goes to the navigator; in step 3 each beacon
// frame, in arrival order, steps it and writes one $PNVBSOL whose trigger_tag is the frame's
// timer field (as received, decimal).
//
// The handlers decide nothing: they run in whatever order the io_context hands them out,
// and only mark; the fixed order of step 1 is the loop's. A signal stops navd before any
// port of its wake-up is read, or during a --delay-ms sleep.
//
// Why this order: the bench makes any aiding bytes (GPS, DVL, Keller answers, ...) that
// precede a trigger readable before it writes the trigger, so reading the trigger port first
// and handling every aiding message before AHRS within a wake applies every fix at the same
// trigger on every run (lockstep determinism). CAN frames are read like the --input ports,
// before the AHRS packets of the same wake (the P3 navigators fuse the wheel encoders). For the
// polled Keller the bench stamps a request with the scenario time reached when it reads it,
// so a request is written before the $PNVBSOL of the AHRS packet whose timer made it due:
// the bench has it when the solution arrives, and the answer comes back before the next
// trigger it precedes. The modem's
// position reports follow the same rule (written before the solution of the sample whose
// timer made them due, so the bench stamps them with that sample's time). No wall clock
// enters the estimate, the wake-ups or the report schedule; only --delay-ms sleeps, and
// only before writing.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "nav/estimator/dvl_navigator.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/estimator/p1_driver.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "aiding_input.hpp"
#include "can_input.hpp"
#include "config.hpp"
#include "descriptor_watch.hpp"
#include "keller_poller.hpp"
#include "modem_link.hpp"
#include "nav/transport/can_socket.hpp"
#include "nav/transport/serial_port.hpp"
#include "output_queue.hpp"
#include "p2_navigator.hpp"
#include "p3_navigator.hpp"
#include "p4_navigator.hpp"
#include "state_link.hpp"
#include "stream_decoder.hpp"

namespace nav::dut {

/// The $PNVBSOL of a navigator's estimate answering trigger `tag` of the `input` role. A
/// non-finite or out-of-range estimate is reported as DEGRADED with empty position fields
/// rather than as numbers.
protocols::navd::Solution to_solution(const estimator::NavSolution& nav, std::uint64_t tag,
                                      std::uint64_t seq, const char* input = "AHRS");

/// Command-line settings of navd.
struct NavdOptions {
  std::string ahrs_path;            ///< 3DM-GX3-25 tty; empty = none (P3, P4 navigators only)
  int ahrs_baud = 115200;           ///< [bit/s]
  std::string gps_path;             ///< NMEA 0183 GPS tty; empty = no GPS
  int gps_baud = 9600;              ///< [bit/s]
  std::string output_path;          ///< tty receiving $PNVBSOL
  int output_baud = 115200;         ///< [bit/s]
  std::string config_path;          ///< YAML filter parameters; empty = defaults
  int delay_ms = 0;                 ///< sleep before writing each solution (test aid) [ms]
  std::vector<InputSpec> inputs;    ///< extra --input ports, in command-line order
  std::optional<ModemSpec> modem;   ///< --modem: acoustic modem line; nullopt = none
  int vehicle_id = 0;               ///< --vehicle-id: this vehicle's id in $PNVBPOS, 0..255
  std::string can_iface;            ///< --can: SocketCAN interface (vcan0, can0); empty = none
  std::string dbc_path;             ///< --dbc: the vehicle's DBC for non-N2K frames; empty = none
};

/// GPS sentence bookkeeping for the exit summary.
struct GpsCounts {
  std::uint64_t gga = 0;         ///< GGA sentences decoded
  std::uint64_t rmc = 0;         ///< RMC sentences decoded
  std::uint64_t vtg = 0;         ///< VTG sentences decoded (counted, not used)
  std::uint64_t hdt = 0;         ///< HDT sentences decoded (heading kept, not used)
  std::uint64_t zda = 0;         ///< ZDA sentences decoded (counted, not used)
  std::uint64_t other = 0;       ///< well-formed sentences of other types (ignored)
  std::uint64_t no_fix = 0;      ///< GGA quality 0 / RMC status V (ignored)
  std::uint64_t incomplete = 0;  ///< fix without a needed field (lat/lon/alt, SOG/COG)
  std::uint64_t bad_fields = 0;  ///< GGA/RMC/VTG/HDT/ZDA whose fields did not decode
};

/// An opened --input port with its front end.
struct ExtraPort {
  InputSpec spec;            ///< what the command line said
  transport::SerialPort port;  ///< the opened tty
};

/// The opened --can socket with its front end.
struct CanPort {
  transport::CanSocket socket;  ///< bound to options.can_iface
  CanInput input;               ///< N2K, plus the --dbc messages when given
};

/// The running DUT. Not movable: the output queue refers to the output port it owns, and
/// the waits on `io` refer to the app.
class NavdApp {
 public:
  /// Takes the opened ports (ahrs unless a P3 navigator runs without one; extras in
  /// options.inputs order; modem when options.modem is set; can when options.can_iface is
  /// set). A P3 navigator's trigger is the first EBIMU --input. `signals` holds SIGTERM and SIGINT; `io`, on
  /// which `signals` was made, is run by run() only and must outlive the app.
  NavdApp(boost::asio::io_context& io, boost::asio::signal_set& signals,
          const NavdOptions& options, const NavdConfig& config,
          std::optional<transport::SerialPort> ahrs,
          std::optional<transport::SerialPort> gps, std::vector<ExtraPort> extras,
          std::optional<transport::SerialPort> modem, std::optional<CanPort> can,
          transport::SerialPort output);
  NavdApp(const NavdApp&) = delete;
  NavdApp& operator=(const NavdApp&) = delete;

  /// Runs until SIGTERM/SIGINT, hang-up of the output, or EOF/hang-up of every input
  /// (AHRS, GPS, every --input, the modem and the CAN socket).
  /// Returns why it stopped (for the summary line).
  std::string run();

  /// One-line summary: packets per port (every --input by message type), rejects by kind,
  /// modem reports sent and heard, solutions written.
  std::string stats_line(const std::string& reason) const;

  /// Bytes the output may hold back before dropping old solutions [bytes].
  static constexpr std::size_t kOutputQueueBytes = 64 * 1024;
  /// Most undecoded bytes held per input port [bytes].
  static constexpr std::size_t kInputBufferBytes = 16 * 1024;
  /// Most bytes read from one port in one wake (the rest waits for the next wake) [bytes].
  static constexpr std::size_t kReadPerWakeBytes = 64 * 1024;
  /// Most CAN frames taken in one wake (the rest waits for the next wake) [frames].
  static constexpr std::size_t kCanFramesPerWake = 4096;

 private:
  /// Reads `port` until EAGAIN (at most kReadPerWakeBytes), passing each chunk to `sink`.
  template <typename Sink>
  void read_port(transport::SerialPort& port, bool& open, Sink&& sink);
  void handle_gps(const protocols::nmea::Sentence& s);
  /// Steps the navigator and writes one solution; false when a signal or output hang-up
  /// says to stop.
  bool handle_ahrs(const protocols::gx3::AccelRateMag& m);
  /// P3: one EBIMU line of the trigger input, with its ordinal: Keller requests due, the
  /// step, one solution. False when a signal or output hang-up says to stop.
  bool handle_ebimu(const AidingInput::EbimuLine& line);
  /// P3: the wheel samples decoded this wake into the navigator (others: dropped).
  void handle_wheels();
  /// P4: one beacon INS frame of the trigger input: the step, one solution named by its
  /// timer. False when a signal or output hang-up says to stop.
  bool handle_beacon(const protocols::beacon_ins::Sample& frame);
  /// Writes the innovations and covariance `stated` and then `solution` after --delay-ms;
  /// false when a signal or output hang-up says to stop.
  bool answer(std::string stated, const protocols::navd::Solution& solution);
  /// Sleeps --delay-ms on the io_context; false when a signal came meanwhile.
  bool wait_delay();
  /// Takes every waiting CAN frame (at most kCanFramesPerWake) into the CAN front end.
  void read_can();
  /// Starts the waits of every open input and of the output not already waiting or ready.
  void arm_waits();
  /// Sleeps until a port, the output or a signal is ready, then runs every handler ready.
  void wait_for_wake();
  /// Whether a handler has marked something for this wake-up.
  bool woken() const;
  /// One wake-up: reads, decodes, handles, writes (steps 1-4 of the diagram).
  void handle_wake();

  boost::asio::io_context& io_;
  boost::asio::signal_set& signals_;
  boost::asio::steady_timer delay_timer_;  ///< --delay-ms
  bool delay_over_ = false;                ///< delay_timer_ expired
  NavdOptions options_;
  std::optional<transport::SerialPort> ahrs_;
  std::optional<transport::SerialPort> gps_;
  transport::SerialPort output_;
  std::optional<DescriptorWatch> ahrs_watch_;  ///< read; set with ahrs_
  std::optional<DescriptorWatch> gps_watch_;  ///< read; set with gps_
  DescriptorWatch output_watch_;  ///< error (hang-up), write (armed while sentences wait)
  bool ahrs_open_ = false;
  bool gps_open_ = false;
  StreamDecoder<protocols::gx3::AccelRateMag> ahrs_decoder_;
  StreamDecoder<protocols::nmea::Sentence> gps_decoder_;
  std::vector<protocols::gx3::AccelRateMag> ahrs_msgs_;  ///< decoded in this wake-up
  std::vector<protocols::nmea::Sentence> gps_msgs_;      ///< decoded in this wake-up
  /// One --input: its port, front end, and whether it is still open.
  struct Extra {
    transport::SerialPort port;
    std::unique_ptr<DescriptorWatch> watch;  ///< read (a pointer: its waits refer to it)
    AidingInput input;
    bool open = true;
    std::optional<KellerPoller> poller;  ///< for a Keller bus: navd is the master
    std::uint64_t write_errors = 0;      ///< requests the line did not take whole
  };
  /// Writes a Keller request to its port without blocking (a short write is counted).
  void write_request(Extra& e, const protocols::Bytes& request);
  /// Writes every Keller request due at the trigger of `timer_ticks` (the AHRS timer, or the
  /// P3 clock), before that trigger's solution (lockstep: see above).
  void write_due_requests(std::uint32_t timer_ticks);
  /// Hands every decoded Keller answer to its poller; P1 values become queued depths.
  void handle_keller_answers();
  std::vector<Extra> extras_;  ///< in command-line order
  /// Writes a report to the modem without blocking; true when the line took it whole (else
  /// it is dropped: receivers reject its remains by checksum).
  bool write_modem(protocols::ByteSpan report);
  /// Decodes modem bytes: logs every $PNVBPOS heard (one line each on stderr), or keeps the
  /// state reports heard for handle_p2().
  void handle_modem_bytes(protocols::ByteSpan bytes);
  /// navigator p2: the iUSBL fixes of this wake, then the state reports heard in it (a fix
  /// waits for the report covering it: p2_navigator.hpp). Other navigators drop the fixes.
  void handle_p2();
  std::optional<transport::SerialPort> modem_;
  std::optional<DescriptorWatch> modem_watch_;  ///< read; set with modem_
  bool modem_open_ = false;
  std::optional<ModemLink> modem_link_;  ///< set with modem_, but for navigator p2
  std::optional<StateLink> state_link_;  ///< set with modem_ for navigator p2
  std::vector<protocols::navd_state::StateReport> reports_;  ///< heard in this wake-up
  OutputQueue out_;
  estimator::FilterParams params_;
  /// Exactly one navigator is set, by the config's `navigator`.
  std::optional<estimator::Navigator> gps_nav_;
  std::optional<estimator::DvlNavigator> dvl_nav_;
  std::optional<estimator::P1Driver> p1_nav_;  ///< navigator: ins, ekf15, upf15, mfins (paper P1)
  std::optional<P2Navigator> p2_nav_;          ///< navigator: p2 (paper P2)
  std::optional<P3Navigator> p3_nav_;  ///< navigator: p3-dr, p3-ekf, p3-ekf-kr (paper P3)
  std::optional<std::size_t> p3_trigger_;  ///< P3: the index in extras_ of the EBIMU trigger
  std::uint64_t p3_wrong_length_ = 0;  ///< P3: EBIMU lines not of p3_ebimu_values values
  std::optional<P4Navigator> p4_nav_;  ///< navigator: p4-ukf, p4-dwt-ukf (paper P4)
  std::optional<std::size_t> p4_trigger_;  ///< P4: the index in extras_ of the beacon trigger
  /// The estimate of whichever navigator runs.
  estimator::NavSolution nav_solution() const;
  /// Status of the last attitude step of whichever navigator runs.
  estimator::AttitudeStatus attitude_status() const;
  /// Hands the DVL velocities decoded this wake to the dead reckoning (dvl navigator only).
  void handle_dvl_velocities();
  std::uint64_t seq_ = 0;
  GpsCounts gps_counts_;
  std::optional<double> last_heading_deg_;  ///< last HDT heading (not used by the filter) [deg]
  std::string stop_reason_;
  std::optional<CanPort> can_;  ///< --can: the socket and its front end
  std::optional<DescriptorWatch> can_watch_;  ///< read; set with can_
  bool can_open_ = false;       ///< the socket has not failed
};

}  // namespace nav::dut
