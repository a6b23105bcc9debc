"""The attention library's input and output: sensor logs, their replay, ROS bags and traces.

- ``sensor_log``: ``SensorLog``, the readings of a logged run, and ``LogFormatError``.
- ``replay``: ``load_log`` (CSV, NPZ or a ROS bag) and ``replay_log``, and the command
  line's goal and map specifications.
- ``rosbag``: a ROS 1 or ROS 2 bag read as a ``SensorLog`` (the optional ``rosbags``
  package), with ``ros_readings``' conversions of its messages and ``ros_tf``'s of its
  TF transforms (the laser's mount, odometry).
- ``trace``: a run recorded to ``.npz`` and read back.

Import from the modules, or the public names from ``attentive_gym.attention``.
"""
