"""A whole attentional-model step as compiled kernels (docs/model.md §2–§8).

- ``records``: the state, constants and outputs of a step as a few flat buffers and
  records (``StateLayout``, ``ModelState``, ``output_dtype``).
- ``step_kernels``: the kernels of one step; on the sonar grid one call, ``attend_many``,
  for one model or many (``attend_one`` per model).
- ``batch``: ``ModelBatch``, models of one configuration stepped in one parallel call,
  as the vector environments use them.

Import from the modules (``ModelBatch`` is also in ``attentive_gym.attention``). This
package imports none of them itself: ``model`` imports ``records`` and ``step_kernels``,
and ``batch`` imports ``model``.
"""
