// SPDX-License-Identifier: MIT
// navd: the reference DUT of navbench. Reads a MicroStrain 3DM-GX3-25 (0xCB packets), an
// NMEA 0183 GPS (GGA/RMC; VTG/HDT/ZDA counted) and any number of extra aiding inputs
// (--input: DVLs, USBL, EBIMU, NMEA; a Keller RS-485 depth sensor polled) from serial ports,
// estimates, and writes one $PNVBSOL solution per AHRS packet to an output serial port
// (docs/dut-contract.md). Its config selects the navigator (gps-ins: AHRS + GPS Kalman filter,
// depth fused; dvl: DVL dead reckoning from a known start, depth fused, paper P0) and the
// attitude source (mahony, or paper P0's raw/ekf/ukf/cf, or the error-state quaternion EKF
// eskf). With --modem it broadcasts its position as $PNVBPOS over an acoustic modem and logs
// the other vehicles'. With --can it reads one SocketCAN bus (NMEA 2000, and the frames of
// the vehicle's DBC given with --dbc): decoded and counted, not fused.
//
// Exit codes: 0 SIGTERM/SIGINT, output hang-up, or every input at EOF/hang-up;
//             2 bad usage or config (a DBC that cannot be loaded or disagrees with the code);
//             3 a port or the CAN interface cannot be opened.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/system/error_code.hpp>
#include <CLI/CLI.hpp>

#include "nav/protocols/dbc.hpp"
#include "nav/transport/can_socket.hpp"

#include "can_input.hpp"
#include "config.hpp"
#include "navd_app.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitUsage = 2;
constexpr int kExitPort = 3;

constexpr const char* kDescription =
    "navd - reference DUT of navbench. Reads a MicroStrain 3DM-GX3-25 AHRS (0xCB packets) and "
    "an optional NMEA 0183 GPS (GGA, RMC; VTG, HDT, ZDA counted) from serial ports (ttys or "
    "pty slaves, raw 8N1), estimates attitude and position, and writes one $PNVBSOL solution "
    "per AHRS packet. The config file (--config) chooses the navigator: gps-ins (default: a "
    "Kalman filter anchored at the first GPS fix, driven by the accelerometer) or dvl (paper "
    "P0: the DVL velocity of every DVL --input rotated by the attitude and integrated from "
    "origin_lat_deg/origin_lon_deg/origin_depth_m; GPS ignored); and the attitude source: "
    "mahony (default: quaternion complementary filter with gyro bias), raw, ekf, ukf or cf "
    "(paper P0's no-filtering, Euler EKF, Euler UKF and PI complementary filter, with the "
    "paper's parameters) or eskf (error-state quaternion EKF: gyro bias and, given the local "
    "Earth field, the magnetometer's hard iron estimated; the magnetometer corrects heading "
    "only and is refused when the field's magnitude or inclination is off; accelerometer "
    "compensated with the DVL velocity). Other "
    "aiding inputs (--input: USBL, EBIMU, NMEA; DVLs under gps-ins) are decoded, counted and "
    "kept, not fused; a Keller RS-485 depth sensor (--input NAME=keller:PATH) is polled and "
    "its depth fused by either navigator. With --modem it shares its position with other "
    "vehicles over an acoustic modem ($PNVBPOS) and counts and logs theirs (not fused). With "
    "--can it reads one SocketCAN bus: NMEA 2000 PGNs 127250, 127251, 127257, 128259, 128267, "
    "129025, 129026 and 129029 (fast packet), and the vehicle's frames described by --dbc "
    "(wheel encoders), decoded and counted, not fused.";

std::string footer() {
  return "Output format: for every AHRS 0xCB packet navd writes exactly one line "
         "$PNVBSOL,AHRS,<tag>,<seq>,<lat_deg>,<lon_deg>,<depth_m>,<vn>,<ve>,<vd>,<roll_deg>,"
         "<pitch_deg>,<yaw_deg>,<status>*hh<CR><LF>: tag is the packet's timer field in "
         "decimal (ticks of 1/62500 s) and names the trigger; seq counts solutions from 0; "
         "latitude/longitude in degrees (+N, +E); depth in metres below mean sea level (+down); "
         "velocity north/east/down in m/s; roll/pitch/yaw (ZYX) in degrees; status ALIGNING "
         "before the first GPS fix (the six position and velocity fields are then empty), OK "
         "after it (dvl navigator: from the first AHRS packet), DEGRADED if the estimate is "
         "not finite or the attitude filter reported a numerical fault at this packet (e.g. "
         "the UKF's Cholesky factorisation failed; the filter recovered); hh is the XOR of the "
         "characters "
         "between '$' and '*' in two upper-case hex digits. Before it, in one write: a "
         "$PNVBINN for each measurement update made at the packet (euler, accel, mag, "
         "gps-position, gps-velocity, depth: innovation and its predicted covariance) and a "
         "$PNVBCOV when the navigator keeps a covariance (docs/dut-contract.md section 4). "
         "Writes never block: up to 64 KiB "
         "of solutions wait for a slow reader, then the oldest unsent ones are dropped.\n\n"
         "Extra inputs: --input NAME=PROTOCOL:PATH[@BAUD], repeatable. NAME is the port's "
         "role in the summary (1-32 of a-z 0-9 _ -, unique, not ahrs/gps/output); PROTOCOL is "
         "nq1 (NavQuest NQ1 lines), pd0 (RDI PD0 ensembles), pd6 (RDI PD6 lines), a50 (Water "
         "Linked A50 packets), ebimu (EBIMU lines), usbl (EvoLogics USBLLONG/USBLANGLES), "
         "nmea (NMEA 0183), keller (Keller RS-485 pressure transmitter) or beacon-ins (paper "
         "P4's beacon INS binary frames); BAUD defaults to "
         "9600 for nmea and keller and 115200 otherwise. Example: "
         "--input dvl=pd0:/dev/pts/5@115200. Every input has its own decoder; its messages are "
         "counted by type, malformed bytes are dropped and counted by reason (checksum, "
         "framing, sync_bytes, overflow_bytes, fields). The estimate uses keller inputs, and "
         "under the dvl navigator the bottom-track velocity of nq1, pd0, pd6 and a50 inputs "
         "(instrument frame = body frame; the last one decoded before each AHRS packet); "
         "under a P3 navigator (p3-dr, p3-ekf, p3-ekf-kr) the first ebimu input is the "
         "trigger (no --ahrs): each line of p3_ebimu_values values is answered, named by its "
         "ordinal, and the wheel encoders come from --can with --dbc; under a P4 navigator "
         "(p4-ukf, p4-dwt-ukf) the first beacon-ins input is the trigger (no --ahrs, --gps "
         "required): each frame is answered, named by its timer field, and the GPS RMC "
         "position (and with p4_rmc_velocity its speed/course) is fused. "
         "All inputs are read in the same loop, the AHRS first, and every aiding message is "
         "handled before the AHRS packets of the same wake-up.\n\n"
         "Keller depth sensor: navd is the bus master. It sends F48 (init) to address 250 "
         "(transparent: the single device on the bus answers) at start, then every "
         "depth_poll_period_s of AHRS timer time (the first a period after the first AHRS "
         "packet) one F73 channel 1 (P1) request, written before "
         "the solution of the AHRS packet that made it due; one request is outstanding at a "
         "time, an unanswered one counts as a timeout at the next poll, exception 32 (not "
         "initialised) makes navd send F48 again. depth = (P1 - depth_atmosphere_pa) / "
         "(depth_density_kgpm3 * 9.80665) is fused as the down position (std depth_std_m) once "
         "a GPS fix has anchored the local plane. Example: --input depth=keller:/dev/pts/6@9600."
         "\n\n"
         "Acoustic modem: --modem PATH[@BAUD] (BAUD default 9600) is the serial line of a modem "
         "in transparent mode, --vehicle-id N (0-255, default 0) this vehicle's id. Once the "
         "position is valid navd writes one line "
         "$PNVBPOS,<id>,<t_s>,<lat_deg>,<lon_deg>,<depth_m>,<std_m>*hh<CR><LF> at once and then "
         "every modem_period_s of AHRS timer time (wrap-safe), each before the solution of the "
         "AHRS packet that made it due: t_s is that packet's timer in seconds (3 decimals; it "
         "wraps with the timer at 68719.476736 s), latitude/longitude in degrees (6 decimals), "
         "depth in metres (2 decimals, -999.99..9999.99), std_m the horizontal 1-sigma per "
         "axis in metres (1 decimal, rounded up, saturated at 999.9); at most 64 bytes, one "
         "modem packet. A write the line does not take whole is dropped and counted, never "
         "waited for. navd reads the modem line like its inputs, decodes the $PNVBPOS of other "
         "vehicles (its own id is ignored), keeps the last one per sender, logs each on stderr "
         "and does not fuse them; the summary adds modem{sent= received= rejected= "
         "peers=[id:count,...] ...}.\n\n"
         "CAN bus: --can IFACE (e.g. vcan0, can0) opens a raw SocketCAN socket on IFACE, read in "
         "the same loop as the serial inputs (before the AHRS packets of the same wake-up). "
         "29-bit frames are NMEA 2000: the eight PGNs above are decoded (129029 fast packets "
         "reassembled per source), other PGNs counted as other. --dbc FILE (optional) is the "
         "vehicle's DBC: frames whose identifier it defines are decoded by it and counted by "
         "message name; WheelEncoderLeft/WheelEncoderRight must agree with navd's wheel encoder "
         "codec (else exit 2). Other frames (11-bit ids not in the DBC, RTR) are rejected and "
         "counted. Nothing from CAN is fused yet; navd keeps the last message of each kind. The "
         "summary adds can{iface= frames= n2k{PGN=..,other=} dbc{Message=..} rejects{...}}.\n\n"
         "Exit codes: 0 on SIGTERM/SIGINT, output hang-up, or when every input reached "
         "EOF/hang-up; 2 bad usage or config (also a --dbc that cannot be loaded or disagrees "
         "with navd); 3 a port or the CAN interface cannot be opened. A one-line summary "
         "(every port's counters) goes to stderr on exit.\n\n"
         "Config keys (--config, a YAML map key: value, SI units):\n" +
         nav::dut::config_keys_help();
}

int run(int argc, char** argv) {
  nav::dut::NavdOptions opt;
  CLI::App app(kDescription, "navd");
  app.footer(footer());
  const auto bauds = nav::transport::SerialPort::supported_bauds();
  app.add_option("--ahrs", opt.ahrs_path,
                 "tty of the 3DM-GX3-25 AHRS streaming 0xCB packets; every packet is a "
                 "trigger answered by one solution (required, but by the P3 navigators, whose "
                 "trigger is the first --input of protocol ebimu, and the P4 navigators, whose is the "
                 "first of protocol beacon-ins)");
  app.add_option("--ahrs-baud", opt.ahrs_baud, "AHRS line rate [bit/s]")
      ->capture_default_str()
      ->check(CLI::IsMember(bauds));
  app.add_option("--gps", opt.gps_path,
                 "tty of the NMEA 0183 GPS (GGA: position, RMC: velocity; VTG, HDT, ZDA counted, "
                 "not used); without it the solution stays ALIGNING with empty position fields");
  app.add_option("--gps-baud", opt.gps_baud, "GPS line rate [bit/s]")
      ->capture_default_str()
      ->check(CLI::IsMember(bauds));
  std::vector<std::string> input_specs;
  app.add_option("--input", input_specs,
                 "extra aiding input NAME=PROTOCOL:PATH[@BAUD], repeatable; PROTOCOL one of " +
                     nav::dut::protocol_names() +
                     " (decoded and counted, not fused, except keller; see below)")
      ->take_all()
      ->allow_extra_args(false);
  std::string modem_spec;
  const CLI::Option* modem_option = app.add_option("--modem", modem_spec,
                 "acoustic modem line PATH[@BAUD] (BAUD default 9600): $PNVBPOS position "
                 "reports (navigator p2: binary state reports) out every modem_period_s, "
                 "other vehicles' reports in (see below)");
  app.add_option("--vehicle-id", opt.vehicle_id,
                 "this vehicle's id in its $PNVBPOS reports (navigator p2: in its state "
                 "reports, 1..p2_vehicles, and the acoustic address of its iUSBL pings)")
      ->capture_default_str()
      ->check(CLI::Range(0, 255));
  app.add_option("--can", opt.can_iface,
                 "SocketCAN interface (e.g. vcan0, can0) carrying NMEA 2000 and the --dbc "
                 "frames; decoded and counted, not fused");
  const CLI::Option* dbc_option =
      app.add_option("--dbc", opt.dbc_path,
                     "the vehicle's DBC file describing its non-NMEA 2000 frames (e.g. the "
                     "wheel encoders of fixtures/crawler.dbc); needs --can")
          ->check(CLI::ExistingFile);
  app.add_option("--output", opt.output_path, "tty the $PNVBSOL solutions are written to")
      ->required();
  app.add_option("--output-baud", opt.output_baud, "output line rate [bit/s]")
      ->capture_default_str()
      ->check(CLI::IsMember(bauds));
  app.add_option("--config", opt.config_path,
                 "YAML file setting filter parameters by name (keys below); unknown keys are "
                 "an error")
      ->check(CLI::ExistingFile);
  std::uint64_t seed = 1;
  app.add_option("--seed", seed,
                 "seed of the particle filters' random draws (navigators upf15, mfins); a "
                 "scenario passes its run's: --seed \"{seed}\"")
      ->capture_default_str();
  app.add_option("--delay-ms", opt.delay_ms,
                 "test aid: sleep this long before writing each solution, simulating a slow "
                 "estimator [ms]")
      ->capture_default_str()
      ->check(CLI::Range(0, 600000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "navd: %s (see navd --help)\n", e.what());
    return kExitUsage;
  }
  if (auto specs = nav::dut::parse_input_specs(input_specs, bauds); specs) {
    opt.inputs = std::move(*specs);
  } else {
    std::fprintf(stderr, "navd: %s\n", specs.error().detail.c_str());
    return kExitUsage;
  }

  if (modem_option->count() > 0) {
    auto spec = nav::dut::parse_modem_spec(modem_spec, bauds);
    if (!spec) {
      std::fprintf(stderr, "navd: %s\n", spec.error().detail.c_str());
      return kExitUsage;
    }
    opt.modem = *spec;
  }

  std::optional<nav::dut::CanInput> can_input;
  if (dbc_option->count() > 0 && opt.can_iface.empty()) {
    std::fprintf(stderr, "navd: --dbc needs --can (see navd --help)\n");
    return kExitUsage;
  }
  if (!opt.can_iface.empty()) {
    if (opt.dbc_path.empty()) {
      can_input.emplace();
    } else {
      auto db = nav::protocols::dbc::load(opt.dbc_path);
      if (!db) {
        std::fprintf(stderr, "navd: --dbc %s: %s\n", opt.dbc_path.c_str(),
                     db.error().detail.c_str());
        return kExitUsage;
      }
      auto in = nav::dut::CanInput::with_dbc(std::move(*db));
      if (!in) {
        std::fprintf(stderr, "navd: --dbc %s: %s\n", opt.dbc_path.c_str(),
                     in.error().detail.c_str());
        return kExitUsage;
      }
      can_input.emplace(std::move(*in));
    }
  }

  nav::dut::NavdConfig config;
  if (!opt.config_path.empty()) {
    auto loaded = nav::dut::load_config(opt.config_path);
    if (!loaded) {
      std::fprintf(stderr, "navd: %s\n", loaded.error().detail.c_str());
      return kExitUsage;
    }
    config = *loaded;
  }
  config.p1.seed = seed;
  if (config.navigator == nav::dut::NavigatorKind::kP2 &&
      (opt.vehicle_id < 1 || opt.vehicle_id > config.p2.vehicles)) {
    std::fprintf(stderr,
                 "navd: navigator p2: --vehicle-id %d is not one of the p2_vehicles ids 1..%d "
                 "(see navd --help)\n",
                 opt.vehicle_id, config.p2.vehicles);
    return kExitUsage;
  }

  const bool p3 = config.navigator == nav::dut::NavigatorKind::kP3;
  const bool has_ebimu =
      std::any_of(opt.inputs.begin(), opt.inputs.end(), [](const nav::dut::InputSpec& i) {
        return i.protocol == nav::dut::InputProtocol::kEbimu;
      });
  if (p3 && (!opt.ahrs_path.empty() || !has_ebimu || opt.can_iface.empty() ||
             opt.dbc_path.empty())) {
    std::fprintf(stderr,
                 "navd: navigator %s: needs an --input NAME=ebimu:PATH (the trigger), --can "
                 "and --dbc with the wheel encoder messages, and no --ahrs (see navd --help)\n",
                 nav::dut::navigator_name(config).c_str());
    return kExitUsage;
  }
  if (p3 && !(can_input && can_input->angle_per_tick(nav::protocols::wheel_encoder::Wheel::kLeft) &&
              can_input->angle_per_tick(nav::protocols::wheel_encoder::Wheel::kRight))) {
    std::fprintf(stderr, "navd: navigator %s: --dbc %s defines no WheelEncoderLeft and "
                 "WheelEncoderRight messages (see fixtures/crawler.dbc)\n",
                 nav::dut::navigator_name(config).c_str(), opt.dbc_path.c_str());
    return kExitUsage;
  }
  const bool p4 = config.navigator == nav::dut::NavigatorKind::kP4;
  const bool has_beacon =
      std::any_of(opt.inputs.begin(), opt.inputs.end(), [](const nav::dut::InputSpec& i) {
        return i.protocol == nav::dut::InputProtocol::kBeaconIns;
      });
  if (p4 && (!opt.ahrs_path.empty() || !has_beacon)) {
    std::fprintf(stderr,
                 "navd: navigator %s: needs an --input NAME=beacon-ins:PATH (the trigger) and "
                 "no --ahrs (see navd --help)\n",
                 nav::dut::navigator_name(config).c_str());
    return kExitUsage;
  }
  if (p4 && opt.gps_path.empty()) {
    std::fprintf(stderr,
                 "navd: navigator %s: needs --gps PATH (the RMC fixes that start and correct "
                 "it; see navd --help)\n",
                 nav::dut::navigator_name(config).c_str());
    return kExitUsage;
  }
  if (!p3 && !p4 && opt.ahrs_path.empty()) {
    std::fprintf(stderr, "navd: --ahrs is required (navigator %s; see navd --help)\n",
                 nav::dut::navigator_name(config).c_str());
    return kExitUsage;
  }

  std::signal(SIGPIPE, SIG_IGN);
  // Caught from here on: a SIGTERM while the ports open stops navd at its first wake-up,
  // with the summary, as one that comes later does.
  boost::asio::io_context io;
  boost::asio::signal_set signals(io);
  boost::system::error_code signal_error;
  signals.add(SIGTERM, signal_error);
  if (!signal_error) signals.add(SIGINT, signal_error);
  if (signal_error) {
    std::fprintf(stderr, "navd: cannot set up signal handling: %s\n",
                 signal_error.message().c_str());
    return kExitUsage;
  }

  auto open_port = [](const std::string& path, int baud) {
    auto port = nav::transport::SerialPort::open(path, baud);
    if (!port) std::fprintf(stderr, "navd: %s\n", port.error().detail.c_str());
    return port;
  };
  std::optional<nav::transport::SerialPort> ahrs;
  if (!opt.ahrs_path.empty()) {
    auto a = open_port(opt.ahrs_path, opt.ahrs_baud);
    if (!a) return kExitPort;
    ahrs.emplace(std::move(*a));
    // A 3DM-GX3-25 streams only once told to: set continuous mode for the 0xCB reply
    // (protocols.md 1a). Its 8-byte 0xC4 reply is skipped by the 0xCB hunt.
    if (auto ok = ahrs->write_all(nav::protocols::gx3::encode_set_continuous(
            nav::protocols::gx3::kCmdAccelRateMag));
        !ok) {
      std::fprintf(stderr, "navd: cannot start the AHRS stream: %s\n",
                   ok.error().detail.c_str());
    }
  }
  std::optional<nav::transport::SerialPort> gps;
  if (!opt.gps_path.empty()) {
    auto g = open_port(opt.gps_path, opt.gps_baud);
    if (!g) return kExitPort;
    gps.emplace(std::move(*g));
  }
  std::vector<nav::dut::ExtraPort> extras;
  std::string extras_text;
  for (const auto& spec : opt.inputs) {
    auto p = open_port(spec.path, spec.baud);
    if (!p) return kExitPort;
    extras.push_back(nav::dut::ExtraPort{spec, std::move(*p)});
    extras_text += " input " + nav::dut::to_string(spec);
  }
  std::optional<nav::transport::SerialPort> modem;
  std::string modem_text;
  if (opt.modem) {
    auto m = open_port(opt.modem->path, opt.modem->baud);
    if (!m) return kExitPort;
    modem.emplace(std::move(*m));
    modem_text = " modem=" + opt.modem->path + "@" + std::to_string(opt.modem->baud) +
                 " vehicle_id=" + std::to_string(opt.vehicle_id);
  }
  std::optional<nav::dut::CanPort> can;
  std::string can_text;
  if (can_input) {
    // Receive timestamps are not used: the P3 navigators take the wheels by count, not time.
    nav::transport::CanSocketOptions can_options;
    can_options.timestamps = false;
    // Its controller's error reports too (bus errors, bus-off, restart): counted, survived.
    can_options.error_classes = nav::protocols::can::kErrAllClasses;
    auto socket = nav::transport::CanSocket::open(opt.can_iface, can_options);
    if (!socket) {
      std::fprintf(stderr, "navd: %s\n", socket.error().detail.c_str());
      return kExitPort;
    }
    can.emplace(nav::dut::CanPort{std::move(*socket), std::move(*can_input)});
    can_text = " can=" + opt.can_iface + " dbc=" + (opt.dbc_path.empty() ? "none" : opt.dbc_path);
  }
  auto output = open_port(opt.output_path, opt.output_baud);
  if (!output) return kExitPort;

  std::fprintf(stderr,
               "navd: running: ahrs=%s@%d gps=%s%s%s%s output=%s@%d config=%s delay=%d ms\n",
               opt.ahrs_path.empty() ? "none" : opt.ahrs_path.c_str(), opt.ahrs_baud,
               gps ? (opt.gps_path + "@" + std::to_string(opt.gps_baud)).c_str() : "none",
               extras_text.c_str(), modem_text.c_str(), can_text.c_str(), opt.output_path.c_str(),
               opt.output_baud, opt.config_path.empty() ? "defaults" : opt.config_path.c_str(),
               opt.delay_ms);

  nav::dut::NavdApp navd(io, signals, opt, config, std::move(ahrs), std::move(gps),
                         std::move(extras), std::move(modem), std::move(can), std::move(*output));
  const std::string reason = navd.run();
  std::fprintf(stderr, "%s\n", navd.stats_line(reason).c_str());
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navd: %s\n", e.what());
    return 1;
  }
}
