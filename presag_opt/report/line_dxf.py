"""The line as a drawing a CAD tool reads: ``line_design.dxf`` (ezdxf), in metres, on named layers.

Two views in one model space, both along the chainage x [m]:

- the **longitudinal profile**, y = height above the rail [m]: the contact wire and the wire the droppers
  hang from as polylines through every mast and dropper of a section, each mast as a vertical line
  between the two wires with its id, each dropper as a line between its clamp points with its id
  (section/from–to/number), the section boundaries as vertical lines;
- the **plan**, developed along the chainage (the survey gives chainages, not coordinates), y = lateral
  offset from the track centre line [m], + to the left: the track centre line and the contact wire's
  staggers through every mast and dropper.

The profile lies above y = 4 m (contact-wire heights) and the plan within the working width about
y = 0, so the views do not overlap.
"""

from __future__ import annotations

from pathlib import Path

from presag_opt.design.line_results import LineDesign

LAYERS = {
    "PROFILE_CONTACT_WIRE": 5,
    "PROFILE_MESSENGER_WIRE": 1,
    "PROFILE_MASTS": 8,
    "PROFILE_DROPPERS": 3,
    "PROFILE_DROPPER_IDS": 3,
    "PROFILE_SECTIONS": 9,
    "PLAN_TRACK_CENTRE_LINE": 8,
    "PLAN_CONTACT_WIRE": 5,
    "PLAN_MAST_IDS": 8,
}
"""Layer names and their colours (AutoCAD colour index)."""

TEXT_HEIGHT = 0.05
"""Height of the dropper and mast ids. [m]"""


def write_dxf(design: LineDesign, path: str | Path) -> Path:
    """Write the profile and the plan of a designed line as DXF (R2010, units metres).

    Parameters
    ----------
    design : LineDesign
        The line as built.
    path : str or Path
        Output file.
    """
    import ezdxf  # imported here: only --dxf pays for it
    from ezdxf import units

    doc = ezdxf.new("R2010")
    doc.units = units.M
    for name, colour in LAYERS.items():
        doc.layers.add(name, color=colour)
    space = doc.modelspace()
    masts = {m.mast: m for m in design.survey.masts}
    for i, sec in enumerate(design.sections):
        ids = [s.from_mast for s in sec.spans] + [sec.spans[-1].to_mast]
        at_masts = [(masts[m].chainage, masts[m].contact_wire_height, masts[m].system_height, masts[m].stagger, m)
                    for m in ids]
        points = sorted([(x, cw, cw + sh, lat) for x, cw, sh, lat, _ in at_masts]
                        + [(d.chainage, d.contact_wire_height, d.messenger_height, d.lateral) for d in sec.droppers])
        space.add_lwpolyline([(x, cw) for x, cw, _, _ in points], dxfattribs={"layer": "PROFILE_CONTACT_WIRE"})
        space.add_lwpolyline([(x, mw) for x, _, mw, _ in points], dxfattribs={"layer": "PROFILE_MESSENGER_WIRE"})
        space.add_lwpolyline([(x, lat) for x, _, _, lat in points], dxfattribs={"layer": "PLAN_CONTACT_WIRE"})
        space.add_line((points[0][0], 0.0), (points[-1][0], 0.0), dxfattribs={"layer": "PLAN_TRACK_CENTRE_LINE"})
        for x, cw, sh, lat, mast in at_masts:
            space.add_line((x, cw), (x, cw + sh), dxfattribs={"layer": "PROFILE_MASTS"})
            space.add_text(mast, height=2 * TEXT_HEIGHT, dxfattribs={"layer": "PROFILE_MASTS"}).set_placement(
                (x, cw + sh + 0.1))
            space.add_text(mast, height=TEXT_HEIGHT, dxfattribs={"layer": "PLAN_MAST_IDS"}).set_placement(
                (x, lat + 0.05))
        for d in sec.droppers:
            space.add_line((d.chainage, d.contact_wire_height), (d.chainage, d.messenger_height),
                           dxfattribs={"layer": "PROFILE_DROPPERS"})
            space.add_text(d.id, height=TEXT_HEIGHT, rotation=90.0,
                           dxfattribs={"layer": "PROFILE_DROPPER_IDS"}).set_placement(
                (d.chainage - 0.02, d.contact_wire_height + 0.05))
        if i:
            x = at_masts[0][0]
            space.add_line((x, 0.0), (x, at_masts[0][1] + at_masts[0][2] + 0.5), dxfattribs={"layer": "PROFILE_SECTIONS"})
    path = Path(path)
    doc.saveas(path)
    return path
