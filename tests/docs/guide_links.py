#!/usr/bin/env python3
"""Every link and image of the built guide resolves: for each HTML page under HTML_DIR, every
href and src that is not an absolute URL names a file of the site, and every #anchor names an
id on its page. External links (http, https, mailto) are listed, not fetched: the test sends no
traffic. Exit 1 naming each broken link.

Usage: guide_links.py HTML_DIR
"""
import html.parser
import os
import sys
import urllib.parse


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links = set(), []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and "name" in a:
            self.ids.add(a["name"])
        for key in ("href", "src"):
            if a.get(key) is not None and not (tag == "link" and key == "href" and
                                               a.get("rel") == "canonical"):
                self.links.append((tag, a[key]))


def main():
    root = os.path.abspath(sys.argv[1])
    pages = {}
    for d, _, files in os.walk(root):
        for f in files:
            if f.endswith(".html"):
                p = Page()
                path = os.path.join(d, f)
                p.feed(open(path, encoding="utf-8").read())
                pages[path] = p
    broken, local, external = [], 0, 0
    for path, page in pages.items():
        for tag, link in page.links:
            url = urllib.parse.urlsplit(link)
            if url.scheme in ("http", "https", "mailto") or link.startswith("//"):
                external += 1
                continue
            if url.scheme:
                broken.append(f"{path}: {link} (scheme {url.scheme})")
                continue
            local += 1
            target = path if not url.path else os.path.normpath(
                os.path.join(os.path.dirname(path), urllib.parse.unquote(url.path)))
            if os.path.isdir(target):
                target = os.path.join(target, "index.html")
            if not os.path.exists(target):
                broken.append(f"{os.path.relpath(path, root)}: {link} (no file)")
                continue
            if url.fragment and target in pages and url.fragment not in pages[target].ids:
                broken.append(f"{os.path.relpath(path, root)}: {link} (no anchor)")
    for b in broken:
        print("BROKEN:", b)
    print(f"{len(pages)} pages, {local} local links and images checked, {len(broken)} broken, "
          f"{external} external links not fetched")
    return 1 if broken or len(pages) < 10 else 0


if __name__ == "__main__":
    sys.exit(main())
