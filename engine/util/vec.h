// Basic vector types shared by the engine. SI units unless a name says otherwise.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ps {
using Vec3 = Eigen::Vector3d;   // position [m], velocity [m/s] or force [N] depending on use
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
}  // namespace ps
