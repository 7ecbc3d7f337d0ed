"""The EKM's hyper-parameters (ekm.config) refuse bad values."""

import pytest

from ekm.config import EKMConfig


@pytest.mark.parametrize("bad", [dict(mapping="both"), dict(neurons=1), dict(priority=0), dict(gamma_d=-1.0),
                                 dict(d_scale=float("nan"))])
def test_config_refuses_bad_values(bad):
    with pytest.raises(ValueError):
        EKMConfig(**bad)
