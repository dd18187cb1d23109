"""The YAML files users write (scenarios, experiments, object sets), read one way.

* :mod:`.yaml_text`: what Drake's ``yaml_load_typed`` does not check in the text (UTF-8, keys
  given twice, sizes, shapes), and where a field is written;
* :mod:`.layers`: a file and its overrides as layers, each loaded over the last, and errors
  that name the layer, the field and its line.

On the ground floor: it imports nothing of gbh_drake but the field rules
(:mod:`gbh_drake.core.ranges`).
"""
