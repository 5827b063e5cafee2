#pragma once
// A trajectory: pose, velocity and acceleration of the platform as functions
// of time since its start. Segments compose into sequences.

#include <memory>
#include <string>
#include <vector>

#include "edsp/kinematics/types.h"

namespace edsp {

struct PoseSample {
  Vector6 pose = Vector6::Zero();          // x y z (m), roll pitch yaw (rad)
  Vector6 velocity = Vector6::Zero();      // per second
  Vector6 acceleration = Vector6::Zero();  // per second squared
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual double duration_s() const = 0;
  // Valid for any t: before 0 the start, after duration_s() the end.
  virtual PoseSample Sample(double t_s) const = 0;
  // Standing still on purpose (a dwell, for a measurement), not a motion
  // that happens to be slow: setpoints say so in their phase.
  virtual bool dwells() const { return false; }
};

// Point to point with a quintic (minimum-jerk) profile: zero velocity and
// acceleration at both ends.
class QuinticMove final : public Trajectory {
 public:
  QuinticMove(const Vector6& from, const Vector6& to, double duration_s);
  // The shortest quintic move whose peak speeds stay within the limits.
  static QuinticMove WithinLimits(const Vector6& from, const Vector6& to, double max_speed_m_s, double max_speed_rad_s);
  double duration_s() const override { return duration_s_; }
  PoseSample Sample(double t_s) const override;

 private:
  Vector6 from_, to_;
  double duration_s_;
};

// Holds a pose.
class Dwell final : public Trajectory {
 public:
  Dwell(const Vector6& at, double duration_s) : at_(at), duration_s_(duration_s) {}
  double duration_s() const override { return duration_s_; }
  bool dwells() const override { return true; }
  PoseSample Sample(double /*t_s*/) const override {
    PoseSample sample;  // velocity and acceleration zero
    sample.pose = at_;
    return sample;
  }

 private:
  Vector6 at_;
  double duration_s_;
};

// center + amplitude·sin(2πft) on one axis, faded in and out over the first
// and last period by a quintic window so it starts and ends at rest.
class Sinusoid final : public Trajectory {
 public:
  Sinusoid(const Vector6& center, int axis, double amplitude, double frequency_hz, int cycles);
  double duration_s() const override { return cycles_ / frequency_hz_; }
  PoseSample Sample(double t_s) const override;

 private:
  Vector6 center_;
  int axis_;
  double amplitude_, frequency_hz_;
  int cycles_;
};

// Named segments played one after another.
class TrajectorySequence final : public Trajectory {
 public:
  void Append(std::string name, std::unique_ptr<Trajectory> segment);
  double duration_s() const override { return total_s_; }
  PoseSample Sample(double t_s) const override;
  // Index and name of the segment playing at t (the last one after the end).
  int SegmentAt(double t_s) const;
  const std::string& SegmentName(int index) const { return segments_[index].name; }
  bool SegmentDwells(int index) const { return segments_[index].trajectory->dwells(); }
  double SegmentStart(int index) const { return segments_[index].start_s; }
  int size() const { return static_cast<int>(segments_.size()); }
  Vector6 EndPose() const;

 private:
  struct Segment {
    std::string name;
    double start_s;
    std::unique_ptr<Trajectory> trajectory;
  };
  std::vector<Segment> segments_;
  double total_s_ = 0.0;
};

}  // namespace edsp
