#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/robot_model.hpp"

namespace cluttertamp::robot {

/// Inverse kinematics of one chain of a RobotModel: from `base` link to `tip` link.
/// Poses are of the tip frame in the base link's frame. Solutions are full robot
/// configurations (RobotModel::variable_count()): the chain's joints solved, every
/// other joint copied from the caller's `seed_configuration`. Every solution lies
/// within the joint limits. Const members are safe to call from several threads.
class CLUTTERTAMP_API IkSolver {
 public:
  virtual ~IkSolver();

  /// Every solution the solver finds, without duplicates, nearest the seed first;
  /// empty when none is found. `random_seed` drives any random choice (same seed,
  /// same answer). Throws std::invalid_argument for a seed of the wrong size.
  virtual std::vector<Eigen::VectorXd> solve(const Eigen::Isometry3d& base_T_tip,
                                             const Eigen::VectorXd& seed_configuration,
                                             std::uint64_t random_seed = 0) const = 0;

  const RobotModel& model() const { return *model_; }
  const std::vector<JointIndex>& chain() const { return chain_; }
  LinkIndex base() const { return base_; }
  LinkIndex tip() const { return tip_; }

  /// The tip pose (in the base frame) of a configuration: forward kinematics of the chain.
  Eigen::Isometry3d forward(const Eigen::VectorXd& q) const;

  /// A ball (base frame, metres) holding every tip position of every configuration:
  /// centred at the first movable joint's origin, with the length of the offsets after
  /// it plus the travel of its prismatic joints as radius. Conservative: a point
  /// outside it is out of reach; one inside may still be.
  struct Reach {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 0.0;
  };
  Reach reach() const;

 protected:
  /// Throws std::invalid_argument when `tip` does not descend from `base`.
  IkSolver(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip);

  std::shared_ptr<const RobotModel> model_;
  LinkIndex base_;
  LinkIndex tip_;
  std::vector<JointIndex> chain_;
  std::vector<JointIndex> path_;  ///< every joint (fixed ones too) from base to tip
};

/// Closed-form IK of the UR family (UR3/5/10/16, e-series): up to 8 solutions per
/// pose. The chain must be six revolute joints standing as a UR arm's (the DH twists
/// pi/2, 0, 0, pi/2, -pi/2, 0 once each axis is turned onto z), in any frames, with any
/// fixed transform after the sixth joint (flange, gripper, TCP). Of the angles 2 pi apart that respect
/// a joint's limits, each solution takes the one nearest the seed.
class CLUTTERTAMP_API UrAnalyticIk final : public IkSolver {
 public:
  /// Reads the UR layout from the model, in whatever frames the URDF puts its joints
  /// (axes along any direction, zero angles anywhere, origins shifted along the axes).
  /// Throws std::invalid_argument when the chain is not a UR arm's.
  UrAnalyticIk(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip);

  std::vector<Eigen::VectorXd> solve(const Eigen::Isometry3d& base_T_tip, const Eigen::VectorXd& seed_configuration,
                                     std::uint64_t random_seed = 0) const override;

  /// The DH parameters read from the model, metres: d1, a2, a3, d4, d5, d6.
  struct Dh {
    double d1, a2, a3, d4, d5, d6;
  };
  const Dh& dh() const { return dh_; }

 private:
  /// Reads the DH layout with joint k's axis taken reversed where bit k of `directions`
  /// is set; false when the chain does not stand so.
  bool adopt_layout(unsigned directions);
  bool reproduces_forward_kinematics() const;

  Dh dh_{};
  double signs_[6] = {1, 1, 1, 1, 1, 1};    ///< DH angle = sign * joint value + offset
  double offsets_[6] = {0, 0, 0, 0, 0, 0};  ///< rad
  Eigen::Isometry3d base_T_joint1_;  ///< fixed transform before the first joint
  Eigen::Isometry3d flange_T_tip_;   ///< fixed transform after the sixth joint's DH frame
};

/// Damped least-squares (Levenberg-Marquardt) IK for any chain, with joint limits and
/// random restarts. Works for redundant chains (7-DOF arms, a mobile base plus arm).
class CLUTTERTAMP_API NumericIk final : public IkSolver {
 public:
  struct Options {
    int restarts = 20;             ///< attempts from random configurations after the seed's
    int max_iterations = 200;      ///< per attempt
    double position_tolerance = 1e-9;     ///< m
    double orientation_tolerance = 1e-9;  ///< rad
    std::size_t max_solutions = 1; ///< stop after this many distinct solutions
    double distinct_tolerance = 1e-4;     ///< rad or m: closer solutions count as one
  };

  NumericIk(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip, Options options);
  NumericIk(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip)
      : NumericIk(std::move(model), base, tip, Options{}) {}

  std::vector<Eigen::VectorXd> solve(const Eigen::Isometry3d& base_T_tip, const Eigen::VectorXd& seed_configuration,
                                     std::uint64_t random_seed = 0) const override;

  const Options& options() const { return options_; }

 private:
  bool descend(const Eigen::Isometry3d& goal, Eigen::VectorXd& q) const;
  Options options_;
};

/// Position and orientation error between two poses: (metres, radians).
CLUTTERTAMP_API std::pair<double, double> pose_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace cluttertamp::robot
