import sys

from animat.experiments.cli import main

sys.exit(main())
