// A client built on the OpenIGTLink library against the server on loopback: it receives the
// instruments' transforms and both TRUS images (size, spacing and matrix as the imager makes
// them), and a transform it sends moves the probe.
#include "igtl/server.h"

#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlTransformMessage.h>

#include <chrono>
#include <cstring>
#include <map>
#include <thread>

#include "engine/ultrasound/from_simulation.h"
#include "engine/util/error.h"
#include "engine/ultrasound/imager.h"
#include "haptics/probe_source.h"
#include "igtl/poses.h"
#include "engine/tools/probe/probe.h"

namespace ps::igtl {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kSide = 96;  // image side [px]: small, so the test stays fast

struct Received {
  std::map<std::string, ::igtl::Matrix4x4> transforms;
  struct Image {
    int dims[3] = {0, 0, 0};
    float spacing[3] = {0, 0, 0};
    ::igtl::Matrix4x4 m;
    int scalar_type = 0;
  };
  std::map<std::string, Image> images;
};

// Reads messages until `done` or the deadline; false on a socket error.
template <class Done>
bool receive_until(::igtl::ClientSocket* s, Received& got, Clock::time_point deadline, Done done) {
  auto header = ::igtl::MessageHeader::New();
  while (!done() && Clock::now() < deadline) {
    header->InitPack();
    const int r = s->Receive(header->GetPackPointer(), header->GetPackSize());
    if (r == -1) continue;  // timeout
    if (r != header->GetPackSize()) return false;
    header->Unpack();
    const std::string type = header->GetDeviceType(), name = header->GetDeviceName();
    if (type == "TRANSFORM") {
      auto t = ::igtl::TransformMessage::New();
      t->SetMessageHeader(header);
      t->AllocatePack();
      if (s->Receive(t->GetPackBodyPointer(), t->GetPackBodySize()) != t->GetPackBodySize()) return false;
      EXPECT_TRUE(t->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY);
      t->GetMatrix(got.transforms[name]);
    } else if (type == "IMAGE") {
      auto im = ::igtl::ImageMessage::New();
      im->SetMessageHeader(header);
      im->AllocatePack();
      if (s->Receive(im->GetPackBodyPointer(), im->GetPackBodySize()) != im->GetPackBodySize()) return false;
      EXPECT_TRUE(im->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY);
      Received::Image& out = got.images[name];
      im->GetDimensions(out.dims);
      im->GetSpacing(out.spacing);
      im->GetMatrix(out.m);
      out.scalar_type = im->GetScalarType();
    } else {
      s->Skip(header->GetBodySizeToRead());
    }
  }
  return true;
}

void send_transform(::igtl::ClientSocket* s, const char* name, const Vec3& p_mm) {
  auto t = ::igtl::TransformMessage::New();
  t->SetDeviceName(name);
  ::igtl::Matrix4x4 m;
  ::igtl::IdentityMatrix(m);
  for (int i = 0; i < 3; ++i) m[i][3] = static_cast<float>(p_mm[i]);
  t->SetMatrix(m);
  t->Pack();
  ASSERT_EQ(s->Send(t->GetPackPointer(), t->GetPackSize()), 1);
}

TEST(IgtlServer, SendsPosesAndImagesAndTakesATrackedProbe) {
  Scene scene = load_scene(PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml");
  ASSERT_GE(scene.tools.index<ProbeTool>(), 0);
  LoopOptions lo;
  lo.log_timing = false;
  PhysicsLoop loop(*scene.sim, lo);
  ServerOptions so;
  so.port = 0;  // the system picks a free one
  so.image_size = kSide;
  Server server(scene, loop, so);
  ASSERT_GT(server.port(), 0);
  haptics::ProbeSource probe_src(scene, server.probe_device());
  loop.add_source(&probe_src);
  server.start();
  loop.start();

  auto client = ::igtl::ClientSocket::New();
  ASSERT_EQ(client->ConnectToServer("127.0.0.1", server.port()), 0);
  client->SetReceiveTimeout(200);
  Received got;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  ASSERT_TRUE(receive_until(client.GetPointer(), got, deadline, [&] {
    return got.transforms.count(kProbeName) && got.transforms.count(needle_device_name("biopsy_1")) &&
           got.images.count(kTransverseName) && got.images.count(kSagittalName);
  }));
  ASSERT_TRUE(got.transforms.count(kProbeName)) << "no Probe transform within 60 s";
  ASSERT_TRUE(got.transforms.count(needle_device_name("biopsy_1")));
  ASSERT_TRUE(got.images.count(kTransverseName)) << "no transverse image within 60 s";
  ASSERT_TRUE(got.images.count(kSagittalName));

  // what the scene shows now (the probe has not moved: no input yet)
  loop.update_snapshot();
  const Snapshot& snap = loop.snapshot();
  std::vector<std::string> names;
  for (const auto& n : scene.spec.needles.needles) names.push_back(n.name);
  for (const NamedPose& p : instrument_poses(snap, names)) {
    SCOPED_TRACE(p.name);
    ASSERT_TRUE(got.transforms.count(p.name));
    const auto& m = got.transforms[p.name];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[r][c], p.m[r][c], 1e-4);
      EXPECT_NEAR(m[r][3], p.m[r][3], 0.05);  // [mm]: the needle sags a little in tissue between snapshots
    }
  }
  us::ProbeView pv;
  ASSERT_TRUE(us::probe_view_from_snapshot(snap, pv));
  const us::UltrasoundAnatomy anatomy = us::anatomy_for_scenario(scene.spec, *scene.model);
  us::UltrasoundSettings set = us::settings_for_probe(*scene.spec.probe);
  set.width = set.height = kSide;
  for (const auto kind : {us::PlaneKind::Transverse, us::PlaneKind::Sagittal}) {
    const us::PlaneImager imager(anatomy, set, kind);
    const Received::Image& im = got.images[kind == us::PlaneKind::Transverse ? kTransverseName : kSagittalName];
    SCOPED_TRACE(kind == us::PlaneKind::Transverse ? "transverse" : "sagittal");
    EXPECT_EQ(im.dims[0], kSide);
    EXPECT_EQ(im.dims[1], kSide);
    EXPECT_EQ(im.dims[2], 1);
    EXPECT_EQ(im.scalar_type, ::igtl::ImageMessage::TYPE_UINT8);
    const double px_mm = imager.image().pixel * 1e3;
    EXPECT_NEAR(im.spacing[0], px_mm, 1e-5);
    EXPECT_NEAR(im.spacing[1], px_mm, 1e-5);
    const Matrix want = image_matrix(imager, pv, kSide, kSide);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(im.m[r][c], want[r][c], c < 3 ? 1e-4 : 1e-3);
    // the centre pixel's world point is the image origin; pixel (0, 0) is half the image away
    const Vec3 corner = imager.pixel_to_world(pv, 0, 0) * 1e3;
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(corner[r], want[r][3] - 0.5 * (kSide - 1) * px_mm * (want[r][0] + want[r][1]), 1e-3);
  }

  // a tracked probe: its first pose is the reference, then 5 mm along its own z axis inserts
  // the probe 5 mm deeper
  const Vec3 tip0 = pv.tip_centre, axis = pv.axis.normalized();
  send_transform(client.GetPointer(), "ProbeToTracker", Vec3(12, -40, 300));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  send_transform(client.GetPointer(), "ProbeToTracker", Vec3(12, -40, 305));
  double moved = 0.0;
  const auto move_deadline = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < move_deadline && moved < 4.9e-3) {
    receive_until(client.GetPointer(), got, Clock::now() + std::chrono::milliseconds(50), [] { return false; });
    if (loop.update_snapshot() && us::probe_view_from_snapshot(loop.snapshot(), pv)) moved = (pv.tip_centre - tip0).dot(axis);
  }
  EXPECT_NEAR(moved, 5e-3, 0.1e-3) << "the probe moved " << moved * 1e3 << " mm along its axis";
  EXPECT_GE(server.transforms_received(), 2);
  EXPECT_GT(server.transforms_sent(), 0);
  EXPECT_GT(server.images_sent(), 0);
  client->CloseSocket();
  loop.stop();
  server.stop();
}

TEST(IgtlServer, APortInUseIsBadInput) {
  Scene scene = load_scene(PROSTATESIM_SOURCE_DIR "/config/demo_cube.yaml");
  LoopOptions lo;
  lo.log_timing = false;
  PhysicsLoop loop(*scene.sim, lo);
  ServerOptions so;
  so.port = 0;
  Server first(scene, loop, so);
  so.port = first.port();
  EXPECT_THROW(Server(scene, loop, so), InputError);
}

}  // namespace
}  // namespace ps::igtl
