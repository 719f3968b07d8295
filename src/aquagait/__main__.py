from aquagait.cli import main

raise SystemExit(main())
