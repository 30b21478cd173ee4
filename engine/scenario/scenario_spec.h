// ScenarioSpec mirrors a scenario file, already converted to SI units (files use mm, kPa, ms;
// conversion happens once, in parse_yaml.cpp). It is the editable form: the instructor editor
// changes a ScenarioSpec, compile_scenario() turns it into an immutable Model.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

// Where in the file a value came from, for error messages.
struct SourceLoc {
  std::string file;
  int line = 0;  // 1-based, 0 unknown
};

struct RegionSpec {
  enum Kind { All, Box, Sphere, HalfSpace } kind = All;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();   // Box [m]
  Vec3 center = Vec3::Zero(); double radius = 0; // Sphere [m]
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();  // HalfSpace: keeps (x-point).n >= 0 [m]
  bool contains(const Vec3& x) const;
};

struct MaterialSpec {
  std::string name;
  std::optional<double> young;     // Young's modulus [Pa]
  std::optional<double> k_e;       // raw shape-memory stiffness override [N/m]
  double density = 1000.0;         // [kg/m^3]
  double damping = 10.0;           // velocity damping rate [1/s]
  bool incompressible = false;     // volume constraint on the component's closed surface
  double k_c = 0.0;                // needle cutting weight [N]
  double k_f = 0.0;                // needle friction weight [N]
  SourceLoc loc;
};

struct MeshShapeSpec {
  std::string file;                // resolved path
  double unit_scale = 1e-3;        // file units -> m
  Vec3 translate = Vec3::Zero();   // [m]
  Vec3 rotate_deg = Vec3::Zero();  // XYZ Euler [deg]
  Vec3 scale = Vec3::Ones();
};

struct ShapeSpec {
  enum Kind { Box, Cylinder, Mesh } kind = Box;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();   // Box corners [m]
  Vec3 base = Vec3::Zero();        // Cylinder base centre [m]
  Vec3 axis = Vec3::UnitZ();       // Cylinder axis (unit)
  double radius = 0.0, length = 0.0;  // Cylinder [m]
  MeshShapeSpec mesh;
};

struct ComponentSpec {
  std::string name;
  std::string kind = "elastic";    // elastic | rigid | active
  std::string material;
  ShapeSpec shape;
  double spacing = 0.0;            // particle spacing h [m]
  bool volumetric = true;          // fill: volumetric | surface
  bool kinematic = true;           // rigid: pose changes only by command
  Vec3 fibre = Vec3::UnitZ();      // active: fibre direction
  double active_stress = 0.0;      // active: stress at activation 1 [Pa]
  double activation = 0.0;         // active: initial activation [0,1]
  SourceLoc loc;
};

struct ConstraintSpec {
  enum Kind { Fix, Displace, HalfSpace, Force } kind = Fix;
  std::string component;           // empty: all components
  RegionSpec region;
  uint8_t axes = 7;                // Fix/Displace axis mask
  Vec3 by = Vec3::Zero();          // Displace [m] / Force total [N]
  double t0 = 0.0, t1 = 0.0;       // ramp [s]
  SourceLoc loc;
};

struct OverrideSpec {
  std::string component;
  RegionSpec region;
  std::optional<double> young, k_e, k_c, k_f, damping;  // [Pa], [N/m], [N], [N], [1/s]
  SourceLoc loc;
};

struct LinkSpec {
  std::string a, b;
  double distance = 0.0;           // particles closer than this are linked [m]
  SourceLoc loc;
};

struct ScenarioSpec {
  std::string file;                // source path
  std::string name;
  double dt = 1e-3;                // tick [s]
  int substeps = 1;
  double duration = 1.0;           // [s]
  Vec3 gravity = Vec3(0, 0, -9.81);  // [m/s^2]
  double rest_kinetic_energy = 1e-7; // --until-rest threshold on kinetic energy [J]
  double rest_hold = 0.05;         // ... held for this long [s]
  bool linear_redistribution = false;  // solver.redistribution: linear (paper literal) | gradient
  std::vector<MaterialSpec> materials;
  std::vector<ComponentSpec> components;
  std::vector<ConstraintSpec> constraints;
  std::vector<OverrideSpec> overrides;
  std::vector<LinkSpec> links;
};

}  // namespace ps
