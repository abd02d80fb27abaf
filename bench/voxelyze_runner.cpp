#include "voxelyze_runner.hpp"

#include <time.h>

#include <cmath>
#include <map>

#include "Voxelyze.h"

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int voxelyze_steps(const VoxelyzeBody& body, int steps, double* seconds) {
  CVoxelyze vx(body.voxel_size);
  std::map<double, CVX_Material*> materials;
  for (const VoxelyzeBody::Voxel& v : body.voxels) {
    CVX_Material*& mat = materials[v.stiffness];
    if (!mat) {
      mat = vx.addMaterial(static_cast<float>(v.stiffness), static_cast<float>(body.density));
      mat->setPoissonsRatio(0);
      mat->setInternalDamping(static_cast<float>(body.bond_damping));
      mat->setGlobalDamping(static_cast<float>(body.global_damping));
      mat->setCollisionDamping(static_cast<float>(body.collision_damping));
      mat->setStaticFriction(static_cast<float>(body.mu_static));
      mat->setKineticFriction(static_cast<float>(body.mu_kinetic));
      mat->setCte(0.01f);  // 1 degree: 1 % of the size
    }
    vx.setVoxel(mat, v.x, v.y, v.z);
  }
  vx.enableFloor(true);
  vx.enableCollisions(body.self_collision);
  vx.setGravity(1.0f);
  const float dt = vx.recommendedTimeStep();
  const double degrees = 100.0 * body.act_amplitude;
  const double t0 = cpu_seconds();
  double time = 0;
  int k = 0;
  for (; k < steps; ++k) {
    const double wave = std::sin(2 * M_PI * body.act_frequency * time);
    vx.setAmbientTemperature(static_cast<float>(degrees * wave), true);
    if (!vx.doTimeStep(dt)) break;
    time += dt;
  }
  *seconds = cpu_seconds() - t0;
  return k;
}
