"""``region_name``: the paper's sonar names s1..s8 for the 0-based front-sonar regions."""

import numpy as np
import pytest

from attentive_gym.attention.regions import region_name


def test_region_index_j_is_sonar_s_j_plus_1():
    assert [region_name(j) for j in range(8)] == [f"s{n}" for n in range(1, 9)]
    assert region_name(np.int64(3), with_index=True) == "s4 (region 3)"


@pytest.mark.parametrize("index", [-1, 8])
def test_an_index_outside_the_front_sonars_is_refused(index):
    with pytest.raises(ValueError, match=r"0\.\.7"):
        region_name(index)
