"""A whole attentional-model step as compiled kernels (docs/model.md §2–§8).

- ``step_kernels``: the kernels of one step; on the sonar grid one call, ``attend_one``.
- ``batch``: ``ModelBatch``, models of one configuration stepped in one parallel call
  (``attend_many``), as the vector environments use them.

Import from the modules (``ModelBatch`` is also in ``attentive_gym.attention``). This
package imports none of them itself: ``model`` imports ``step_kernels``, and ``batch``
imports ``model``.
"""
