"""Screenshots of the built documentation site in headless Chromium (Debian's, through
Playwright), to look at what a reader sees.

    mkdocs build --strict && python tools/screenshot_docs.py   # site/screenshots/*.png

One 1280x900 screenshot each of the front page, the getting-started tutorial
(top, and its search section), an API page, the CLI reference and the gallery
(top, and the fish's section).
"""

from __future__ import annotations

import sys
from pathlib import Path

SITE = Path(__file__).resolve().parents[1] / "site"
CHROMIUM = Path("/usr/bin/chromium")
PAGES = {
    "front": "index.html",
    "tutorial": "getting-started.html",
    "tutorial-search": "getting-started.html#your-first-search",
    "api": "api/sim.html",
    "cli": "cli.html",
    "gallery": "gallery.html",
    "gallery-fish": "gallery.html#fish",
}


def main() -> int:
    from playwright.sync_api import sync_playwright

    if not (SITE / "index.html").is_file():
        print(f"no site at {SITE}: run mkdocs build first", file=sys.stderr)
        return 2
    out = SITE / "screenshots"
    out.mkdir(exist_ok=True)
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM))
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        for name, address in PAGES.items():
            file, _, anchor = address.partition("#")
            page.goto((SITE / file).as_uri() + (f"#{anchor}" if anchor else ""))
            page.wait_for_timeout(500)
            page.screenshot(path=out / f"{name}.png")
            print(f"wrote {out / name}.png ({page.title()})")
        browser.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
