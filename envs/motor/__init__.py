"""Motor control: the paper's motor controllers of the fish and the dolphin (swim, turn, fins) and
navigation over them; they map a few parameters to muscle activations.

May import physics, bodies and checks.
"""
