// An io_context run on threads of its own (one unless asked for more), for clients, servers
// and drivers under test; stopped and joined when destroyed.
#pragma once

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <thread>
#include <vector>

namespace igms::testing {

class IoThread {
 public:
  explicit IoThread(int threads = 1) : guard_(io_.get_executor()) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { io_.run(); });
  }
  ~IoThread() { Stop(); }
  IoThread(const IoThread&) = delete;
  IoThread& operator=(const IoThread&) = delete;

  // Ends the loop (pending handlers are dropped) and joins the threads.
  void Stop() {
    guard_.reset();
    io_.stop();
    for (std::thread& t : threads_)
      if (t.joinable()) t.join();
  }
  boost::asio::io_context& io() { return io_; }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> guard_;
  std::vector<std::thread> threads_;
};

}  // namespace igms::testing
