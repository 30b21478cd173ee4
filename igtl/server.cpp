#include "igtl/server.h"

#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlServerSocket.h>
#include <igtlTransformMessage.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "engine/realtime/snapshot_tap.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"
#include "engine/util/error.h"
#include "igtl/poses.h"

namespace ps::igtl {

namespace {
// Reads exactly n bytes from a socket with a short receive timeout. `started`: some bytes of this
// message were read already (then it waits up to ~2 s for the rest). -1: nothing there (only
// when !started), 0: the client is gone or stalled, 1: read.
int read_exact(::igtl::Socket* s, void* buf, int n, bool started) {
  auto* p = static_cast<char*>(buf);
  int got = 0, idle = 0;
  while (got < n) {
    const int r = s->Receive(p + got, n - got, 0);
    if (r > 0) {
      got += r;
      idle = 0;
    } else if (r == -1) {  // timeout
      if (got == 0 && !started) return -1;
      if (++idle > 2000) return 0;
    } else {
      return 0;
    }
  }
  return 1;
}

std::vector<uint8_t> packed(::igtl::MessageBase* m) {
  m->Pack();
  const auto* b = static_cast<const uint8_t*>(m->GetPackPointer());
  return std::vector<uint8_t>(b, b + m->GetPackSize());
}
}  // namespace

struct Server::Impl {
  ::igtl::ServerSocket::Pointer server;
  std::vector<::igtl::ClientSocket::Pointer> clients;
  SnapshotTap tap;
  std::vector<std::string> needle_names;
  explicit Impl(int every) : tap(every) {}
};

Server::Server(const Scene& scene, PhysicsLoop& loop, const ServerOptions& opt) : scene_(scene), opt_(opt) {
  if (opt.port < 0 || opt.port > 65535) throw InputError("", 0, "--igtl-port", "expected a TCP port 0-65535, got " + std::to_string(opt.port));
  if (!(opt.transform_hz > 0) || !(opt.image_hz > 0)) throw InputError("", 0, "--igtl-rate", "rates must be > 0 Hz");
  const double dt = scene.model->dt;
  const int every = std::max(1, static_cast<int>(std::lround(1.0 / (opt.transform_hz * dt))));
  impl_ = std::make_unique<Impl>(every);
  for (const auto& n : scene.spec.needles.needles) impl_->needle_names.push_back(n.name);
  impl_->server = ::igtl::ServerSocket::New();
  if (impl_->server->CreateServer(opt.port) < 0)
    throw InputError("", 0, "--igtl-port", "cannot listen on TCP port " + std::to_string(opt.port) + " (in use?)");
  port_ = impl_->server->GetServerPort();
  if (opt.port != 0) port_ = opt.port;
  loop.add_source(&impl_->tap);
}

Server::~Server() { stop(); }

void Server::start() {
  stop_.store(false);
  server_thread_ = std::thread([this] { serve(); });
  if (scene_.spec.probe) image_thread_ = std::thread([this] { image_loop(); });
}

void Server::stop() {
  stop_.store(true);
  cv_.notify_all();
  if (image_thread_.joinable()) image_thread_.join();
  if (server_thread_.joinable()) server_thread_.join();
  if (impl_) {
    for (auto& c : impl_->clients) c->CloseSocket();
    impl_->clients.clear();
    if (impl_->server) impl_->server->CloseSocket();
  }
  clients_.store(0);
}

void Server::image_loop() {
  us::UltrasoundAnatomy anatomy = us::anatomy_for_scenario(scene_.spec, *scene_.model);
  us::UltrasoundSettings set = us::settings_for_probe(*scene_.spec.probe);
  if (opt_.image_size > 0) set.width = set.height = opt_.image_size;
  us::BiplaneImager imager(anatomy, set);
  Snapshot snap;
  uint64_t version = 0;
  us::ProbeView probe;
  us::UltrasoundScene sc;
  const auto period = std::chrono::duration<double>(1.0 / opt_.image_hz);
  while (!stop_.load()) {
    const auto t0 = std::chrono::steady_clock::now();
    if (impl_->tap.take(snap, version)) {
      us::probe_view_from_snapshot(snap, probe);  // no probe drawn: keeps the last pose
      us::scene_from_snapshot(snap, probe, sc);
      imager.render(sc);
      std::vector<std::vector<uint8_t>> msgs;
      for (us::PlaneImager* im : {&imager.transverse(), &imager.sagittal()}) {
        const us::UsImage& img = im->image();
        auto m = ::igtl::ImageMessage::New();
        m->SetDeviceName(im->kind() == us::PlaneKind::Transverse ? kTransverseName : kSagittalName);
        m->SetDimensions(img.width, img.height, 1);
        const float px = static_cast<float>(img.pixel * 1e3);
        m->SetSpacing(px, px, px);
        m->SetScalarType(::igtl::ImageMessage::TYPE_UINT8);
        m->SetNumComponents(1);
        m->SetEndian(::igtl::ImageMessage::ENDIAN_LITTLE);
        m->AllocateScalars();
        std::memcpy(m->GetScalarPointer(), img.pixels.data(), img.pixels.size());
        Matrix mat = image_matrix(*im, probe, img.width, img.height);
        ::igtl::Matrix4x4 im4;
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c) im4[r][c] = mat[r][c];
        m->SetMatrix(im4);
        msgs.push_back(packed(m.GetPointer()));
      }
      std::lock_guard<std::mutex> lk(mu_);
      images_ = std::move(msgs);
      images_fresh_ = true;
    }
    // at most image_hz, and at most a third of a core (physics and the window come first)
    const auto spent = std::chrono::steady_clock::now() - t0;
    const auto wait = std::max<std::chrono::duration<double>>(period - spent, 2.0 * spent);
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait_for(lk, wait, [&] { return stop_.load(); });
  }
}

void Server::serve() {
  Snapshot snap;
  uint64_t version = 0;
  auto header = ::igtl::MessageHeader::New();
  std::vector<std::vector<uint8_t>> out;
  while (!stop_.load()) {
    // new clients (the wait is this loop's pause: ~200 passes a second)
    ::igtl::ClientSocket::Pointer c = impl_->server->WaitForConnection(5);
    if (c.IsNotNull()) {
      c->SetReceiveTimeout(1);
      c->SetSendTimeout(2000);
      impl_->clients.push_back(c);
    }
    // incoming messages
    for (size_t k = 0; k < impl_->clients.size();) {
      ::igtl::ClientSocket* cs = impl_->clients[k].GetPointer();
      bool alive = true;
      for (int n = 0; n < 64 && alive; ++n) {  // a burst at most per pass
        header->InitPack();
        const int r = read_exact(cs, header->GetPackPointer(), header->GetPackSize(), false);
        if (r < 0) break;
        if (r == 0) { alive = false; break; }
        header->Unpack();
        if (std::strcmp(header->GetDeviceType(), "TRANSFORM") == 0) {
          auto t = ::igtl::TransformMessage::New();
          t->SetMessageHeader(header);
          t->AllocatePack();
          if (read_exact(cs, t->GetPackBodyPointer(), t->GetPackBodySize(), true) <= 0) { alive = false; break; }
          if (!(t->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY)) continue;
          ::igtl::Matrix4x4 m;
          t->GetMatrix(m);
          Mat3 rot;
          Vec3 p;
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) rot(i, j) = m[i][j];
            p[i] = m[i][3] * 1e-3;
          }
          if (!rot.allFinite() || !p.allFinite()) continue;
          const std::string name = header->GetDeviceName();
          if (name.rfind("ProbeTo", 0) == 0) probe_dev_.set_pose(rot, p);
          else if (name.rfind("NeedleTo", 0) == 0) needle_dev_.set_pose(rot, p);
          else continue;
          transforms_received_.fetch_add(1);
        } else {
          const int64_t body = static_cast<int64_t>(header->GetBodySizeToRead());
          std::vector<char> skip(static_cast<size_t>(std::min<int64_t>(body, 1 << 20)));
          for (int64_t left = body; left > 0 && alive;) {
            const int n2 = static_cast<int>(std::min<int64_t>(left, static_cast<int64_t>(skip.size())));
            if (read_exact(cs, skip.data(), n2, true) <= 0) alive = false;
            left -= n2;
          }
        }
      }
      if (!alive) {
        cs->CloseSocket();
        impl_->clients.erase(impl_->clients.begin() + static_cast<std::ptrdiff_t>(k));
      } else {
        ++k;
      }
    }
    clients_.store(static_cast<int>(impl_->clients.size()));
    // outgoing: poses of the newest snapshot, then the images when new ones are ready
    out.clear();
    int poses = 0;
    if (impl_->tap.take(snap, version))
      for (const NamedPose& p : instrument_poses(snap, impl_->needle_names)) {
        auto t = ::igtl::TransformMessage::New();
        t->SetDeviceName(p.name.c_str());
        ::igtl::Matrix4x4 m;
        for (int r = 0; r < 4; ++r)
          for (int cc = 0; cc < 4; ++cc) m[r][cc] = p.m[r][cc];
        t->SetMatrix(m);
        out.push_back(packed(t.GetPointer()));
        ++poses;
      }
    int images = 0;
    {
      std::lock_guard<std::mutex> lk(mu_);
      if (images_fresh_) {
        for (auto& m : images_) out.push_back(std::move(m));
        images = static_cast<int>(images_.size());
        images_.clear();
        images_fresh_ = false;
      }
    }
    if (out.empty() || impl_->clients.empty()) continue;
    for (size_t k = 0; k < impl_->clients.size();) {
      bool ok = true;
      for (const auto& m : out) ok = ok && impl_->clients[k]->Send(m.data(), static_cast<int>(m.size())) == 1;
      if (!ok) {
        impl_->clients[k]->CloseSocket();
        impl_->clients.erase(impl_->clients.begin() + static_cast<std::ptrdiff_t>(k));
      } else {
        ++k;
      }
    }
    transforms_sent_.fetch_add(poses);
    images_sent_.fetch_add(images);
    clients_.store(static_cast<int>(impl_->clients.size()));
  }
}

}  // namespace ps::igtl
