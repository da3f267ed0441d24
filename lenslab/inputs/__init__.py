"""What every input must pass before lenslab decodes it: size limits (:mod:`~lenslab.inputs.limits`),
side files that are regular files of bounded size (:mod:`~lenslab.inputs.sidefile`) and structured text
(YAML, XML, TOML, JSON) parsed without tags, entities or unbounded nesting (:mod:`~lenslab.inputs.safeload`).

It sits below both :mod:`lenslab.io` and :mod:`lenslab.lenses`, which both read files from strangers.
"""
