// The OpenIGTLink server of `prostatesim run --igtl-port N` (docs/igtl.md): 3D Slicer
// (SlicerOpenIGTLink), PLUS or any OpenIGTLink client connects to it over TCP and
//  - receives TRANSFORM messages for the probe and each needle tip (igtl/poses.h names and
//    frames) at `transform_hz`, from snapshots the physics thread hands over (a SnapshotTap:
//    a copy every few ticks, never waiting), so the server never slows the physics;
//  - receives IMAGE messages of both TRUS planes (uint8, one slice, pose in the matrix) at up to
//    `image_hz`, made from those snapshots by the ultrasound imager on a thread of their own that
//    takes at most a third of a core (it waits twice its compute time between frames);
//  - sends TRANSFORM messages in: a name starting with "ProbeTo" (PLUS: ProbeToTracker) moves the
//    probe, one starting with "NeedleTo" the active needle, through the TrackedDevices
//    (igtl/tracked_device.h) that the run polls as input devices. Other messages are skipped.
// One thread accepts clients, reads their messages and sends; the imaging thread renders. Any
// number of clients; a client that goes away is dropped.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/realtime/physics_loop.h"
#include "engine/sim/scene.h"
#include "igtl/tracked_device.h"

namespace ps::igtl {

struct ServerOptions {
  int port = 18944;                // OpenIGTLink's usual port; 0: any free port (port() says which)
  double transform_hz = 50.0;      // instrument poses [Hz of simulated time]
  double image_hz = 10.0;          // TRUS images, at most [Hz wall]
  int image_size = 0;              // image side [px]; 0: the probe's ultrasound settings
};

class Server {
 public:
  // Opens the port (InputError naming --igtl-port when it cannot) and adds its snapshot tap
  // (engine/realtime/snapshot_tap.h) to the loop's sources: construct before loop.start().
  Server(const Scene& scene, PhysicsLoop& loop, const ServerOptions& opt);
  ~Server();                       // stops
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  void start();
  void stop();                     // joins the threads, closes the sockets (idempotent)
  int port() const { return port_; }

  // Tracked instruments, fed by incoming TRANSFORMs (poll them through haptics sources).
  TrackedDevice& probe_device() { return probe_dev_; }
  TrackedDevice& needle_device() { return needle_dev_; }

  // counters (any thread)
  int clients() const { return clients_.load(); }
  int64_t transforms_sent() const { return transforms_sent_.load(); }
  int64_t images_sent() const { return images_sent_.load(); }
  int64_t transforms_received() const { return transforms_received_.load(); }

 private:
  struct Impl;
  void serve();
  void image_loop();

  const Scene& scene_;
  ServerOptions opt_;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
  TrackedDevice probe_dev_{"OpenIGTLink ProbeTo*"}, needle_dev_{"OpenIGTLink NeedleTo*"};
  std::thread server_thread_, image_thread_;
  std::atomic<bool> stop_{false};
  std::mutex mu_;                  // guards the image slot below and wakes the imaging thread
  std::condition_variable cv_;
  std::vector<std::vector<uint8_t>> images_;   // packed IMAGE messages ready to send
  bool images_fresh_ = false;
  std::atomic<int> clients_{0};
  std::atomic<int64_t> transforms_sent_{0}, images_sent_{0}, transforms_received_{0};
};

}  // namespace ps::igtl
