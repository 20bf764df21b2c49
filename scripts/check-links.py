#!/usr/bin/env python3
"""Checks every internal link of the built guide (docs/book, from `mdbook build docs`) and of the
README: the target file exists and, for a link with #anchor, the target page has that id.
Exits 1 listing each broken link; external (http, https, mailto) links are not followed."""
import html.parser
import re
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

ROOT = Path(__file__).resolve().parent.parent
BOOK = ROOT / "docs" / "book"


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links = set(), []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        for key in ("href", "src"):
            if a.get(key):
                self.links.append(a[key])


def parse(path, cache={}):
    if path not in cache:
        p = Page()
        p.feed(path.read_text(encoding="utf-8"))
        cache[path] = p
    return cache[path]


def check_book(broken):
    pages = sorted(BOOK.rglob("*.html"))
    if not pages:
        broken.append(f"{BOOK}: no pages (run `mdbook build docs` first)")
    for page in pages:
        if page.name in ("print.html", "toc.html", "404.html"):
            continue
        for link in parse(page).links:
            u = urlsplit(link)
            if u.scheme or link.startswith("//"):
                continue
            target = page if not u.path else (page.parent / unquote(u.path)).resolve()
            if not target.exists():
                broken.append(f"{page.relative_to(ROOT)}: {link} (no such file)")
            elif u.fragment and target.suffix == ".html" and unquote(u.fragment) not in parse(target).ids:
                broken.append(f"{page.relative_to(ROOT)}: {link} (no such anchor)")


def check_markdown(path, broken):
    text = path.read_text(encoding="utf-8")
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    for link in re.findall(r"\]\(([^)\s]+)\)", text):
        u = urlsplit(link)
        if u.scheme:
            continue
        if u.path and not (path.parent / unquote(u.path)).exists():
            broken.append(f"{path.relative_to(ROOT)}: {link} (no such file)")


def main():
    broken = []
    check_book(broken)
    check_markdown(ROOT / "README.md", broken)
    check_markdown(ROOT / "CHANGELOG.md", broken)
    for b in broken:
        print(b)
    print(f"links: {len(broken)} broken", file=sys.stderr)
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
