"""Design record of a 32 m-class four-section concrete-pump boom (Z fold): the second machine of issue 28.

``BOOM32`` is a :class:`~models.pump_truck.parameters.PumpTruckParameters` of four sections (joint 1 a direct
cylinder drive, joints 2–4 lever-and-link drives), sized by the same code as the 42 m record
(:func:`models.pump_truck.statics.sizing`: worst case pipe filled, full reach, cylinder housings and rods, levers and
links counted): bores 180/180/180/100 mm, every holding pressure ≤ 80 % of 350 bar, transmission angles ≥ 22 deg,
retracted lengths ≥ stroke + dead length (``python -m flexlib.models.pump_truck.record32`` prints the table).

Sources looked for and what they gave (public data; no data sheet with section lengths, masses, pin coordinates or
cylinder bores of a 28–32 m boom was found):

* Equipment World, "Making mud flow better, Putzmeister America debuts two new concrete pumps" (2014) and
  concretepumping.com, "Putzmeister's new 32Z-Meter boom pump" (1999): the Putzmeister 32Z-Meter is a four-section
  "Multi-Z" boom (the 38Z went from four to five sections), horizontal reach 92 ft = 28.0 m, unfolding height
  25 ft 3 in = 7.7 m; the 2014 32Z weighs 3 250 lb less than its predecessor (no boom weight given).
* Schwing (schwinglatinoamerica.com, "New pump boom telescopes for low-clearance efficiency"): the standard Schwing
  31 m boom reaches 87 ft = 26.5 m horizontally and 102 ft = 31.1 m vertically.
* O. Lenord et al. (cited in the review of doi:10.1155/2014/943847): a four-section boom test rig; G. Cazzulani et
  al., Automation in Construction 20 (2011): lever-and-link joint drives; no pin coordinates or bores published.
* System pressure 350 bar, pipe DN125, 4 m end hose and steel: as the 42 m record (same makers, same class of
  hydraulics and delivery line; :mod:`models.pump_truck.parameters`).

Engineering choices (this record): section lengths 8.0/7.0/6.8/6.2 m = 28.0 m (horizontal reach of the 32Z;
vertical reach 28 m + joint 1 about 3.5–4 m above ground ≈ 32 m); masses 1600/1000/650/350 kg (200 → 56 kg/m root to
tip, the 42 m record's 244 → 59 kg/m scaled down: 3.6 t of sections against its 5.85 t, about the ratio of the
lengths squared); boxes tapering 400 × 620 → 250 × 320 mm; Z fold (joints 2 and 4 fold up, joint 3 down) as on the
Multi-Z boom; the 42 m record's lever-and-link base design (``FourBar.scaled``) at scales 0.75/0.55/0.25 and its
joint-1 drive scaled by 0.9, chosen from a small sweep of scales for bores inside 100–280 mm with margin (joint 4:
the 80 mm bore would need about 330 bar on its cap side, above the 280 bar allowed); turret 1.8 t, radius of
gyration 1.0 m.
"""

from __future__ import annotations

from .parameters import DirectDrive, FourBar, PumpTruckParameters, SectionSpec, Turret

__all__ = ["BOOM32"]

_SECTION_SOURCE = ("length: 28.0 m in all = horizontal reach of the Putzmeister 32Z-Meter (92 ft, concretepumping.com "
                   "1999); mass and b, h: engineering choice, the 42 m record's mass per metre and taper scaled to a "
                   "32 m boom (record32 docstring); t: sized here so the box weighs the target mass")
_LINKAGE_SOURCE = ("engineering choice (no published pin coordinates found): the 42 m record's lever-and-link base "
                   "design (parameters._BASE) scaled for the 32 m boom so that every bore lies in 100-280 mm at "
                   "<= 80 % of 350 bar (record32 docstring)")

BOOM32 = PumpTruckParameters(
    sections=(SectionSpec(8.0, 1600.0, 0.40, 0.62, _SECTION_SOURCE), SectionSpec(7.0, 1000.0, 0.35, 0.52,
                                                                                  _SECTION_SOURCE),
              SectionSpec(6.8, 650.0, 0.30, 0.42, _SECTION_SOURCE), SectionSpec(6.2, 350.0, 0.25, 0.32,
                                                                                 _SECTION_SOURCE)),
    linkages=tuple(FourBar(**{**vars(FourBar.scaled(scale, fold)), "source": _LINKAGE_SOURCE})
                   for scale, fold in ((0.75, +1), (0.55, -1), (0.25, +1))),
    joint1=DirectDrive(H=(0.9, -1.98), c=(1.224, 0.0),
                       source=("engineering choice: the 42 m record's joint-1 drive (H = (1.0, -2.2), c = (1.36, 0) "
                               "m) scaled by 0.9; range -5 ... 80 deg as there; bore 180 mm")),
    turret=Turret(mass=1800.0, J_slew=1800.0, height=1.0,
                  source="order of magnitude for a 32 m pump turret: 1.8 t, radius of gyration 1.0 m (J = 1800 * 1^2)"),
    source=("32 m class, four sections, Z fold (Putzmeister 32Z-Meter: four-section Multi-Z boom, 28.0 m horizontal "
            "reach; Schwing 31 m: 26.5 m horizontal, 31.1 m vertical reach); system pressure 350 bar, pipe, hose and "
            "steel as the 42 m record; section masses and linkage proportions: engineering choice (record32 "
            "docstring)"),
)

if __name__ == "__main__":
    from .parameters import describe

    print(describe(BOOM32))
