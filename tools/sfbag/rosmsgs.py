"""The ROS 2 message types sf-bag reads and writes, in a rosbags typestore.

std_msgs/Header, geometry_msgs/Vector3, nav_msgs/Odometry and
geometry_msgs/PoseStamped are built into rosbags' ROS 2 Humble store;
marine_acoustic_msgs (BSD-3) is registered here from its definition text
(fields as published; comments shortened)."""

from rosbags.typesys import Stores, get_typestore, get_types_from_msg

PING_INFO = """
# Center frequency of sonar in Hz (0 if unavailable)
float32 frequency
# Speed of sound (m/s) used to calculate ranges (0 if unavailable)
float32 sound_speed
# Sonar reported -3db beamwidths, radians; may be empty
float32[] tx_beamwidths
float32[] rx_beamwidths
"""

SONAR_IMAGE_DATA = """
bool    is_bigendian
uint32  DTYPE_UINT8 = 0
uint32  DTYPE_INT8 = 1
uint32  DTYPE_UINT16 = 2
uint32  DTYPE_INT16 = 3
uint32  DTYPE_UINT32 = 4
uint32  DTYPE_INT32 = 5
uint32  DTYPE_UINT64 = 6
uint32  DTYPE_INT64 = 7
uint32  DTYPE_FLOAT32 = 8
uint32  DTYPE_FLOAT64 = 9
uint32  dtype
# the number of beams associated with the image
uint32 beam_count
# The actually pixel data in row-major (beam_index major) format
uint8[] data
"""

PROJECTED_SONAR_IMAGE = """
# Single scan from an imaging sonar. The Z-axis is centered in the plane of the
# fan ("forward"), with X up; each beam has an azimuth (rotation about X).
# The header time is the time the ping was transmitted.
std_msgs/Header header
PingInfo ping_info
geometry_msgs/Vector3[] beam_directions
# Center of each range bin in meters; not necessarily equally spaced or from zero.
float32[] ranges
SonarImageData image
"""

# sonarfusion's own: nav_state_t's exact values beside the Odometry (docs/ros2.md).
NAV_STATE = """
# sonarfusion nav_state_t, exact: NED world, FRD body, ZYX roll-pitch-yaw (rad).
# nav_msgs/Odometry on the NAV topic carries the same pose in ENU/FLU, but
# through a quaternion (angles back to ~1e-16 rad); this keeps the bits.
std_msgs/Header header
float64[3] position_ned
float64[3] rpy
float64[3] velocity_ned
float64 altitude
"""

NAVSTATE = "sonarfusion_msgs/msg/NavState"
PSI = "marine_acoustic_msgs/msg/ProjectedSonarImage"
PING = "marine_acoustic_msgs/msg/PingInfo"
DATA = "marine_acoustic_msgs/msg/SonarImageData"
ODOM = "nav_msgs/msg/Odometry"
POSE = "geometry_msgs/msg/PoseStamped"

# dtype -> (numpy type code, bits, signed, float)
DTYPES = {
    0: ("u1", 8, False, False), 1: ("i1", 8, True, False),
    2: ("u2", 16, False, False), 3: ("i2", 16, True, False),
    4: ("u4", 32, False, False), 5: ("i4", 32, True, False),
    6: ("u8", 64, False, False), 7: ("i8", 64, True, False),
    8: ("f4", 32, True, True), 9: ("f8", 64, True, True),
}


def typestore():
    ts = get_typestore(Stores.ROS2_HUMBLE)
    typs = {}
    typs.update(get_types_from_msg(PING_INFO, PING))
    typs.update(get_types_from_msg(SONAR_IMAGE_DATA, DATA))
    typs.update(get_types_from_msg(PROJECTED_SONAR_IMAGE, PSI))
    typs.update(get_types_from_msg(NAV_STATE, NAVSTATE))
    ts.register(typs)
    return ts
