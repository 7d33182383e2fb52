"""The simulator's ROS face over the library: the ROS interface both packages share (`interface`: topics,
QoS, core rows -> messages, the node lifecycle, parameter files), the on-board sensors' messages
(`sensor_messages`) and the simulator node (`node`)."""
