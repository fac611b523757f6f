"""Profile modification: tip relief, loaded contact with load sharing, Hertz contact stress.

After Wang et al. (2024) and Han (n.d.); docs/modification.md. Public names:

- :mod:`.relief`: relief curves, :class:`TipRelief`, :class:`ProfileModification`, height/length
  conversion, recommended amounts (:func:`recommended_relief`)
- :mod:`.contact`: :func:`loaded_contact` (single/double contact decision, K_TPM, load sharing,
  the relief's transmission error), :class:`LoadedContact`
- :mod:`.stress`: Hertz line contact along the path of contact
- ``slice_contact``: :func:`slice_contact`, loaded tooth contact analysis of spur and
  helical pairs by the slice method (Pasternak-coupled slices, Ajmi & Velex 2005), at one torque
  or a ladder (:class:`SliceContact`, :class:`SliceOptions`)
- :mod:`.lead`: lead modifications and misalignment (:class:`LeadModification`,
  :class:`Misalignment`), and :class:`FlankModification`, everything that opens the gap
"""

from gear_dyn.modification.contact import (
    ContactState,
    LoadedContact,
    PathView,
    PiecewiseSignal,
    contact_state,
    loaded_contact,
)
from gear_dyn.modification.lead import FlankModification, LeadModification, Misalignment
from gear_dyn.modification.relief import (
    CURVE_EXPONENTS,
    CURVES,
    RULES,
    ProfileModification,
    ReliefRecommendation,
    TipRelief,
    height_from_length,
    length_from_height,
    long_relief_length,
    recommended_relief,
    recommended_reliefs,
    relief_shape,
    tangential_load_per_width,
)
from gear_dyn.modification.slice_contact import (
    SliceContact,
    SliceOptions,
    pasternak_solve,
    slice_contact,
)
from gear_dyn.modification.stress import (
    contact_stress,
    effective_modulus,
    hertz_line_contact,
    profile_curvature,
)

__all__ = [
    "CURVES",
    "CURVE_EXPONENTS",
    "RULES",
    "ContactState",
    "FlankModification",
    "LeadModification",
    "LoadedContact",
    "Misalignment",
    "PathView",
    "PiecewiseSignal",
    "ProfileModification",
    "ReliefRecommendation",
    "SliceContact",
    "SliceOptions",
    "TipRelief",
    "contact_state",
    "contact_stress",
    "effective_modulus",
    "height_from_length",
    "hertz_line_contact",
    "length_from_height",
    "loaded_contact",
    "pasternak_solve",
    "long_relief_length",
    "profile_curvature",
    "recommended_relief",
    "recommended_reliefs",
    "relief_shape",
    "slice_contact",
    "tangential_load_per_width",
]
