"""A contact ellipse outside Kalker's tables names the study key that made it (issue 36, item 9)."""

from __future__ import annotations

import pytest

from squealcore.errors import InputError
from stages.cases import A_OVER_B_RANGE, check_contact_shape
from stages.config import load_study


@pytest.mark.parametrize("geometry,field", [("profiles", "operating.lateral_displacement"),
                                            ("manual", "contact.rail_head_radius")])
def test_the_message_names_the_users_key_not_a_over_b(geometry, field):
    study = load_study(None, True, [f'contact.geometry="{geometry}"', "operating.lateral_displacement=0.02"])
    low, high = A_OVER_B_RANGE
    check_contact_shape(study, low)  # the ends of the covered range pass
    check_contact_shape(study, high)
    with pytest.raises(InputError) as e:
        check_contact_shape(study, 19.45)
    assert e.value.field == field
    assert "a/b = 19.4" in e.value.message and "geometry.a_over_b" not in str(e.value)
