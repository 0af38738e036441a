// SPDX-License-Identifier: MIT
#include "lines/bench_line.hpp"

namespace nav::bench {

Result<BenchLine> BenchLine::open_serial(const std::string& port, int baud) {
  if (port == "pty") {
    auto p = transport::Pty::open();
    if (!p) return tl::unexpected(p.error());
    return BenchLine(std::move(*p));
  }
  auto s = transport::SerialPort::open(port, baud);
  if (!s) return tl::unexpected(s.error());
  return BenchLine(std::move(*s));
}

Result<BenchLine> BenchLine::open_can(const std::string& iface,
                                      const transport::CanSocketOptions& options) {
  auto sock = transport::CanSocket::open(iface, options);
  if (!sock) return tl::unexpected(sock.error());
  return BenchLine(std::move(*sock));
}

BenchLine BenchLine::on_bus(const std::string& iface) { return BenchLine(iface); }

int BenchLine::fd() const {
  if (const auto* p = std::get_if<transport::Pty>(&end_)) return p->master();
  if (const auto* s = std::get_if<transport::SerialPort>(&end_)) return s->fd();
  if (const auto* c = std::get_if<transport::CanSocket>(&end_)) return c->fd();
  return -1;
}

std::string BenchLine::path() const {
  if (const auto* p = std::get_if<transport::Pty>(&end_)) return p->slave_path();
  if (const auto* s = std::get_if<transport::SerialPort>(&end_)) return s->path();
  if (const auto* c = std::get_if<transport::CanSocket>(&end_)) return c->ifname();
  return std::get<std::string>(end_);
}

void BenchLine::flush() const {
  if (const auto* p = std::get_if<transport::Pty>(&end_)) p->flush_to_slave();
}

void BenchLine::discard_unread() const {
  if (const auto* p = std::get_if<transport::Pty>(&end_)) p->discard_unread();
}

}  // namespace nav::bench
