"""The views' colours, one palette for Rerun and the Foxglove layout: the levels' orange and red, one colour per
wheelset (none of them the levels'), the sensors' mounts after the wheelsets' colours, the estimator's sides
beside the ground truth's grey tones."""
GREEN, ORANGE, RED, GREY = (60, 180, 75), (245, 130, 48), (230, 25, 75), (128, 128, 128)
YELLOW = (200, 160, 0)
WHEELSET_COLORS = [(31, 119, 180), (188, 189, 34), (148, 103, 189), (140, 86, 75)]   # blue, olive, purple, brown
MOUNT_COLORS = WHEELSET_COLORS + [(23, 190, 207), (227, 119, 194), (127, 127, 127), (255, 187, 120)]
ESTIMATE_COLORS = ((31, 119, 180), (148, 103, 189))          # left, right; the ground truth in grey tones
TRUTH_COLORS = ((90, 90, 90), (170, 170, 170))
