"""Simulator node: placeholder and starting point for the simulator node.

For now it only starts, logs one line and spins until Ctrl-C (SIGINT) or SIGTERM, so that the
`railderail-simulator` command and `ros2 run railderail simulator` resolve. The real node (stepping
the vehicle model and publishing railderail_msgs) replaces the body of `main`.
"""
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


def main() -> int:
    rclpy.init()
    node = None
    try:  # from here on, Ctrl-C (KeyboardInterrupt) or SIGTERM ends the node cleanly
        node = Node("railderail_simulator")
        node.get_logger().info("railderail simulator node started (placeholder: publishes nothing yet)")
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
