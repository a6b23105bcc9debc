"""The tracker of the ``tracker`` kinematics mode (docs/model.md §10): the objects of the
laser scan tracked over time.

- ``segmentation``: a scan's points split into segments, foreground from background.
- ``association``: segments matched to tracks (gated minimum-cost assignment).
- ``kalman``: the constant-velocity and static Kalman filters of a track.
- ``tracker``: ``Tracker`` and its compiled ``track_step``, with the track table the model
  outputs (``TrackTable``).
- ``track_regions``: the tracks' speeds and directions per attention region (the channels
  the feature maps read).
- ``free_space``: free-space evidence of motion (an echo inside space an earlier scan saw
  through), which weighs the tracks' probability of moving when
  ``AttentionConfig.free_space_evidence`` is on.

Import from the modules; the public names of the model are in ``attentive_gym.attention``.
"""
