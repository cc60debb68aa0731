"""sf-bag: ROS 2 bags <-> sonarfusion LCM logs (tools/sf-bag, docs/ros2.md)."""
