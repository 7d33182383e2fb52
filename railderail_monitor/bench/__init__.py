"""The ROS product's group of `railderail bench` (`ros`: publish rate, alert latency, the recorder)."""
