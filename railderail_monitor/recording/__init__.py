"""Recordings: the recorder node (`recorder`, MCAP and rosbag2's metadata `bag`), reading and replaying a
recording (`replay`), recovering a cut-off one (`recover`), and EN 14363's assessment of a run or a
recording (`assess`)."""
