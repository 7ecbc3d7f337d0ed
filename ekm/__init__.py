"""Extended Kohonen Maps for learned sensorimotor control of a Khepera-like robot (Low 2002).

``import ekm`` stays light: the command line (``ekm.cli``) imports the other packages inside its commands.
"""

__version__ = "0.1.0"
