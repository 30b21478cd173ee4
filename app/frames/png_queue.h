// PNG encoding off the render path: the renderer hands a frame's pixels to a writer thread and
// goes on with the next frame (stbi's PNG encoder takes ~35 ms a frame at 640x480 here, several
// times the render). The queue is bounded (memory stays flat on long replays): push() waits only
// when `max_pending` frames are already waiting. Buffers are recycled, so a warm replay does not
// allocate per frame. Each file is written atomically (temp + rename).
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ps::frames {

class PngQueue {
 public:
  explicit PngQueue(int max_pending = 6);
  ~PngQueue();  // finishes the queue (errors dropped: call finish() to see them)
  // A buffer for the next frame (recycled from written frames when possible).
  std::vector<uint8_t> take_buffer();
  // Queues one image (rows top-down; 3 channels = RGB, 1 = grayscale, e.g. ultrasound). With
  // `fxaa` (RGB only) the writer antialiases it before encoding (render::fxaa_rgb).
  // Rethrows a write error of an earlier frame.
  void push(const std::string& path, int width, int height, std::vector<uint8_t>&& rgb, int channels = 3,
            bool fxaa = false);
  // Waits for every queued frame; rethrows the first write error.
  void finish();
  int written() const;

 private:
  struct Job {
    std::string path;
    int w = 0, h = 0, channels = 3;
    bool fxaa = false;
    std::vector<uint8_t> rgb;
  };
  void run();
  const size_t max_pending_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Job> jobs_;
  std::vector<std::vector<uint8_t>> free_;
  bool stop_ = false;
  bool busy_ = false;
  int written_ = 0;
  std::exception_ptr error_;
  std::vector<uint8_t> aa_out_;   // writer thread only: the antialiased image
  std::vector<uint8_t> aa_luma_;   // and its scratch
  std::thread thread_;
};

}  // namespace ps::frames
