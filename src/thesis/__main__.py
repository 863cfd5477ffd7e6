import sys

from thesis.cli import main

sys.exit(main())
