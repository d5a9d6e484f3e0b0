// What the stack's nodes say about perception (stack_node.cpp, perception_node.cpp):
// the topics, and types::Obstacle, types::Track and the believed pose as ROS 2
// messages and back, every field kept.
//   /detections              specht_msgs/Obstacles, the car's frame: a detector frame
//   /localization/odometry   nav_msgs/Odometry, frame "map": the box-centre pose the
//                            stack believes when a detector frame comes, stamped
//                            with the frame's time (where perception places it)
//   /perception/tracks       specht_msgs/Tracks, frame "map": one tracker cycle
//   /perception/obstacles    specht_msgs/Obstacles, frame "map": the frame's detections
#pragma once

#include <vector>

#include "specht/io/ros_messages.h"
#include "specht/sim/simulator.h"
#include "specht/types/obstacle.h"
#include "specht/types/track.h"

namespace specht::pipeline::internal {

inline constexpr char kDetectionsTopic[] = "/detections";
inline constexpr char kLocalizationTopic[] = "/localization/odometry";
inline constexpr char kTracksTopic[] = "/perception/tracks";
inline constexpr char kObstaclesTopic[] = "/perception/obstacles";
inline constexpr char kVehicleStateTopic[] = "/vehicle_state";
inline constexpr char kEndOfDrive[] = "end of drive";  // VehicleState.stop when no time limit ended it

io::ros::Obstacles ObstaclesToRos(const std::vector<types::Obstacle>& obstacles, Stamp stamp, const char* frame);
std::vector<types::Obstacle> ObstaclesFromRos(const io::ros::Obstacles& m);

io::ros::Tracks TracksToRos(const std::vector<types::Track>& tracks, Stamp stamp);
std::vector<types::Track> TracksFromRos(const io::ros::Tracks& m);

io::ros::Odometry PoseToRos(const sim::Pose2& box_centre, Stamp stamp);
sim::Pose2 PoseFromRos(const io::ros::Odometry& m);

}  // namespace specht::pipeline::internal
