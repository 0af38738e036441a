// SPDX-License-Identifier: MIT
// navd's generic extra inputs (`--input NAME=PROTOCOL:PATH[@BAUD]`): the spec parser and the
// per-port front end. An AidingInput runs one StreamDecoder over the protocol's tri-state
// codec, counts messages by type and rejects by reason, and keeps the last decoded message.
// Pure (no I/O): navd_app.cpp reads the port and feeds the bytes. A Keller bus input is
// polled: its AidingInput decodes the answers, keller_poller.hpp decides what to ask.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/beacon_ins.hpp"
#include "nav/protocols/ebimu.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "nav/protocols/keller_bus.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"
#include "stream_decoder.hpp"

namespace nav::dut {

/// Protocols an extra input can speak.
enum class InputProtocol {
  kNq1,    ///< LinkQuest NavQuest NQ1 lines ("nq1")
  kPd0,    ///< Teledyne RDI PD0 binary ensembles ("pd0")
  kPd6,    ///< Teledyne RDI PD6 ASCII lines ("pd6")
  kA50,    ///< Water Linked DVL-A50 packets ("a50")
  kEbimu,  ///< E2BOX EBIMU ASCII lines ("ebimu")
  kUsbl,   ///< EvoLogics USBLLONG / USBLANGLES ("usbl")
  kNmea,    ///< NMEA 0183 sentences ("nmea")
  kKeller,  ///< Keller RS-485 bus answers, polled by navd ("keller")
  kBeaconIns,  ///< paper P4's beacon INS binary frames ("beacon-ins")
};

/// The protocol's name on the command line, e.g. "pd0".
std::string_view protocol_name(InputProtocol p);

/// "nq1, pd0, pd6, a50, ebimu, usbl, nmea, keller, beacon-ins" (for --help and errors).
std::string protocol_names();

/// Baud used when the spec gives none: 9600 for NMEA and Keller, 115200 otherwise [bit/s].
int default_baud(InputProtocol p);

/// One `--input NAME=PROTOCOL:PATH[@BAUD]`.
struct InputSpec {
  std::string name;                             ///< role, e.g. "dvl"; [a-z0-9_-], 1..32 chars
  InputProtocol protocol = InputProtocol::kNmea;  ///< what the port speaks
  std::string path;                             ///< tty path
  int baud = 115200;                            ///< line rate [bit/s]
};

/// A port as the command line gives it: "PATH[@BAUD]".
struct PortAddress {
  std::string path;  ///< tty path, non-empty
  int baud = 0;      ///< line rate [bit/s]
};

/// Parses "PATH[@BAUD]" (BAUD after the last '@', one of `bauds`; default_baud without it).
/// The error detail is the reason only ("BAUD 'x' is not a number", "unsupported BAUD n",
/// "empty PATH"), for the caller to place in its own message.
Result<PortAddress> parse_path_baud(std::string_view text, const std::vector<int>& bauds,
                                    int default_baud);

/// Parses one spec. NAME: 1..32 of [a-z0-9_-], not "ahrs", "gps" or "output"; PROTOCOL one
/// of protocol_names(); PATH non-empty; BAUD (after the last '@') one of `bauds`. The error
/// detail is one line naming the spec.
Result<InputSpec> parse_input_spec(std::string_view text, const std::vector<int>& bauds);

/// Parses every spec and refuses a NAME used twice.
Result<std::vector<InputSpec>> parse_input_specs(const std::vector<std::string>& texts,
                                                 const std::vector<int>& bauds);

/// "name=protocol:path@baud".
std::string to_string(const InputSpec& spec);

/// Reject counters of one input: the stream decoder's plus frames whose fields did not decode.
struct InputRejects {
  RejectCounts stream;         ///< checksum, framing, sync_bytes, overflow_bytes
  std::uint64_t fields = 0;    ///< well-framed messages whose fields did not decode
};

/// Front end of one extra input port.
class AidingInput {
 public:
  /// The last decoded message, whatever the protocol (monostate before the first).
  using Message = std::variant<std::monostate, protocols::navquest_nq1::Nq1,
                               protocols::rdi_pd0::Ensemble, protocols::rdi_pd6::Line,
                               protocols::waterlinked_a50::Packet, protocols::ebimu::Line,
                               protocols::evologics::Notification, protocols::nmea::Sentence,
                               protocols::keller::Response, protocols::beacon_ins::Sample>;

  /// max_buffer: bound on undecoded bytes for every protocol but PD0, whose ensembles can
  /// be 64 KiB long and get kPd0BufferBytes [bytes].
  AidingInput(std::string name, InputProtocol protocol, std::size_t max_buffer);

  /// Decodes bytes as they arrive; counts and records every completed message.
  void feed(protocols::ByteSpan bytes);

  const std::string& name() const { return name_; }
  InputProtocol protocol() const { return protocol_; }
  std::uint64_t messages() const;  ///< messages counted by type (well-framed and decoded)
  /// Messages by type, e.g. {"BI": 3, "BS": 3} for PD6; unknown types are "other".
  const std::map<std::string, std::uint64_t>& by_type() const { return by_type_; }
  InputRejects rejects() const;
  std::size_t buffered() const;  ///< undecoded bytes held
  const Message& last() const { return last_; }

  /// Keller answers decoded since the last call, in stream order (cleared by the call);
  /// always empty for other protocols. navd hands them to its KellerPoller.
  std::vector<protocols::keller::Response> take_keller_answers();

  /// Vehicle velocity of the last DVL message that carried a valid one, in the frame the
  /// DVL reports it (PD0/NQ1: as configured, PD6 :BI/:BE, A50 wrz: DVL frame) [m/s].
  const std::optional<std::array<double, 3>>& last_velocity_mps() const { return velocity_; }

  /// The last valid DVL velocity decoded since the previous call (nullopt if none; cleared
  /// by the call). navd's DVL dead reckoning takes it before the AHRS packets of a wake.
  std::optional<std::array<double, 3>> take_velocity() {
    if (!velocity_new_) return std::nullopt;
    velocity_new_ = false;
    return velocity_;
  }

  /// One iUSBL ping: its USBLLONG and the NVBRELATT of the same measurement time and
  /// address that followed it (paper P2's fix, p2_fix.hpp).
  struct RelativeFix {
    protocols::evologics::UsblLong position;
    protocols::evologics::RelativeAttitude attitude;
  };
  /// The iUSBL fixes completed since the last call, in stream order (cleared by the call);
  /// always empty for other protocols. An NVBRELATT that does not follow the USBLLONG of its
  /// ping is counted (counters_text's `unpaired_nvbrelatt`, shown when not 0).
  std::vector<RelativeFix> take_relative_fixes();

  /// One EBIMU line and its ordinal: the LF bytes the port received before the line's own
  /// LF, counted from the port's first byte, in every line whether it decodes or not (the
  /// trigger tag of docs/dut-contract.md, "trigger_tag by kind of trigger device").
  struct EbimuLine {
    std::uint64_t ordinal = 0;
    protocols::ebimu::Line line;
  };
  /// The EBIMU lines decoded since the last call, in stream order (cleared by the call);
  /// always empty for other protocols.
  std::vector<EbimuLine> take_ebimu_lines();

  /// The beacon INS frames decoded since the last call, in stream order (cleared by the
  /// call); always empty for other protocols. Under a P4 navigator the first beacon-ins
  /// input is the trigger.
  std::vector<protocols::beacon_ins::Sample> take_beacon_frames();

  /// Whether the protocol is a DVL's (nq1, pd0, pd6, a50).
  bool is_dvl() const;

  /// "messages=N{type=n ...} rejects{checksum=.. framing=.. sync_bytes=.. overflow_bytes=..
  /// fields=..}".
  std::string counters_text() const;

  /// Most undecoded bytes a PD0 input holds: one whole ensemble of 65 537 bytes fits [bytes].
  static constexpr std::size_t kPd0BufferBytes = 72 * 1024;

 private:
  void on_message(const protocols::navquest_nq1::Nq1& m);
  void on_message(const protocols::rdi_pd0::Ensemble& m);
  void on_message(const protocols::rdi_pd6::Line& m);
  void on_message(const protocols::waterlinked_a50::Packet& m);
  void on_message(const protocols::ebimu::Line& m);
  void on_message(const protocols::evologics::Notification& m);
  void on_message(const protocols::nmea::Sentence& m);
  void on_message(const protocols::keller::Response& m);
  void on_message(const protocols::beacon_ins::Sample& m);
  void count(const std::string& type) { ++by_type_[type]; }
  void set_velocity(const std::array<double, 3>& v) {
    velocity_ = v;
    velocity_new_ = true;
  }

  using Decoder = std::variant<StreamDecoder<protocols::navquest_nq1::Nq1>,
                               StreamDecoder<protocols::rdi_pd0::Ensemble>,
                               StreamDecoder<protocols::rdi_pd6::Line>,
                               StreamDecoder<protocols::waterlinked_a50::Packet>,
                               StreamDecoder<protocols::ebimu::Line>,
                               StreamDecoder<protocols::evologics::Notification>,
                               StreamDecoder<protocols::nmea::Sentence>,
                               StreamDecoder<protocols::keller::Response>,
                               StreamDecoder<protocols::beacon_ins::Sample>>;
  static Decoder make_decoder(InputProtocol protocol, std::size_t max_buffer);

  std::string name_;
  InputProtocol protocol_;
  Decoder decoder_;
  std::map<std::string, std::uint64_t> by_type_;
  std::uint64_t field_errors_ = 0;
  Message last_;
  std::optional<std::array<double, 3>> velocity_;
  bool velocity_new_ = false;  ///< velocity_ set since the last take_velocity()
  std::vector<protocols::keller::Response> keller_answers_;  ///< not yet taken
  std::optional<protocols::evologics::UsblLong> last_long_;  ///< awaiting its NVBRELATT
  std::vector<RelativeFix> relative_fixes_;                  ///< not yet taken
  std::uint64_t unpaired_relative_ = 0;  ///< NVBRELATT not after its ping's USBLLONG
  std::uint64_t line_feeds_ = 0;          ///< EBIMU: LF bytes received so far
  std::vector<EbimuLine> ebimu_lines_;    ///< not yet taken
  std::vector<protocols::beacon_ins::Sample> beacon_frames_;  ///< not yet taken
};

}  // namespace nav::dut
