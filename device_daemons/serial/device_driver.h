// DeviceDriver: what the serial side of every daemon shares. It owns the SerialLink, keeps
// the published LinkStatus (state, counters, message), stamps readings, and can poll the
// device by writing a request at a fixed rate. A device's driver derives from it, parses
// the bytes and says when the device has answered (MarkConnected).
//
// Threading: everything runs on the io_context's thread, callbacks included; status() is
// thread-safe.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <mutex>
#include <string>

#include "device_daemons/serial/serial_link.h"
#include "igms/devices.pb.h"

namespace igms::devices {

class DeviceDriver {
 public:
  using StatusFn = std::function<void(const LinkStatus&)>;

  DeviceDriver(boost::asio::io_context& io, SerialLinkOptions link, std::string name,
               StatusFn on_status);
  virtual ~DeviceDriver() = default;
  DeviceDriver(const DeviceDriver&) = delete;
  DeviceDriver& operator=(const DeviceDriver&) = delete;

  void Start();
  void Stop();  // also to be called before destruction, then the io thread stopped
  LinkStatus status() const;
  const std::string& name() const { return name_; }

 protected:
  // The port was (re)opened: initialise the device and start polling.
  virtual void OnOpened() = 0;
  virtual void OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) = 0;
  // Parser counters, copied into the status.
  virtual uint64_t bad_frames() const = 0;
  virtual uint64_t garbage_bytes() const = 0;

  void Write(std::string bytes) { link_.Write(std::move(bytes)); }
  // Writes `request` now and then every 1/hz seconds until StopPolling or a reopen.
  void StartPolling(double hz, std::string request);
  void StopPolling();
  // The device answered: the published state becomes CONNECTED.
  void MarkConnected();
  // Fills a stamp for a reading that ended at now_ns and counts it.
  void StampReading(Stamp* stamp, int64_t now_ns, uint64_t device_time_us = 0);

  boost::asio::io_context& io_;

 private:
  void OnState(LinkState state, const std::string& message);
  void ArmPoll();
  void Publish(const std::function<void(LinkStatus&)>& change);

  std::string name_;
  StatusFn on_status_;
  SerialLink link_;
  boost::asio::steady_timer poll_timer_;
  std::chrono::nanoseconds poll_period_{0};
  std::string poll_request_;
  bool answered_ = false;
  uint64_t sequence_ = 0;
  mutable std::mutex mutex_;
  LinkStatus status_;
};

}  // namespace igms::devices
