"""Pictures of models and structures: SVG, PNG (matplotlib) and TikZ, without Graphviz
(:mod:`delkit.drawing.draw`; duck-typed, so it imports no model class).
"""
