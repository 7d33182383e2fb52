"""Speed supervision against the critical derailment speed of each curve ahead, as ETCS supervises speed
(ERA SUBSET-026 §3.13): the constants and the braking curves to one target (`curves`), the streaming
supervisor with its levels, live inputs and brake command (`supervisor`), the odometer's confidence interval
(`odometry`) and the closed loop of `railderail simulate --supervision` (`loop`). No ROS; docs/supervision.md."""
