"""A rule's code hash moves with the code it runs, not with its docstrings or comments."""

import hashlib
import zlib

from thesis import provenance

CODE = '''"""Module docstring."""

def f(x):
    """What f is."""
    return x + 1  # a comment


class C:
    """A class."""

    def g(self):
        """Only a docstring."""
'''


def _digest(tmp_path, text):
    path = tmp_path / "m.py"
    path.write_text(text)
    return provenance.source_digest(path)


def test_docstrings_comments_and_layout_leave_the_digest(tmp_path):
    edited = (CODE.replace("What f is.", "What f is, in more words.")
              .replace("# a comment", "# another comment")
              .replace('"""Module docstring."""', '"""Module docstring,\n\nlonger."""')
              .replace("x + 1", "x  +  1"))
    assert edited != CODE
    assert _digest(tmp_path, edited) == _digest(tmp_path, CODE)


def test_a_change_of_code_moves_the_digest(tmp_path):
    base = _digest(tmp_path, CODE)
    assert _digest(tmp_path, CODE.replace("x + 1", "x + 2")) != base
    assert _digest(tmp_path, CODE.replace('"""Only a docstring."""',
                                          '"""Only a docstring."""\n        return 1')) != base
    # A string that is not the first statement is code.
    assert _digest(tmp_path, CODE.replace("return x + 1", 'y = "s"\n    return x + 1')) != base


def test_an_unparsable_file_is_hashed_byte_for_byte(tmp_path):
    assert _digest(tmp_path, "def (:\n") == b"def (:\n"


def test_code_version_of_the_package_is_stable_and_named_by_subpackage():
    assert provenance.code_version("physics") == provenance.code_version("physics")
    assert provenance.code_version("physics") != provenance.code_version("gaits")
    assert len(provenance.code_version()) == 16


def test_digests_are_kept_on_disk_by_content_and_a_bad_entry_is_recomputed(tmp_path,
                                                                          monkeypatch):
    """A second process reads the digest of the same bytes from the disk cache instead of
    parsing again; an unreadable entry is computed again and rewritten."""
    monkeypatch.setenv("THESIS_DIGEST_CACHE", str(tmp_path / "cache"))
    provenance._text_digest.cache_clear()
    want = provenance._syntax_digest(CODE.encode())
    assert _digest(tmp_path, CODE) == want
    entries = list(provenance.digest_cache_dir().iterdir())
    assert [p.name for p in entries] == [hashlib.sha256(CODE.encode()).hexdigest()]
    provenance._text_digest.cache_clear()  # as a new process
    entries[0].write_bytes(zlib.compress(b"kept"))
    assert _digest(tmp_path, CODE) == b"kept"  # read, not parsed
    provenance._text_digest.cache_clear()
    entries[0].write_bytes(b"not zlib")
    assert _digest(tmp_path, CODE) == want
    assert zlib.decompress(entries[0].read_bytes()) == want
    provenance._text_digest.cache_clear()


def test_without_a_home_directory_the_digest_is_computed(tmp_path, monkeypatch):
    """Where Path.home() raises, or returns "~" unexpanded (Python 3.11 without a home),
    nothing is written (not a "~" folder in the working directory)."""
    def no_home():
        raise RuntimeError("Could not determine home directory.")
    monkeypatch.delenv("THESIS_DIGEST_CACHE", raising=False)
    monkeypatch.chdir(tmp_path)
    for home in (staticmethod(no_home), staticmethod(lambda: provenance.Path("~"))):
        monkeypatch.setattr(provenance.Path, "home", home)
        provenance._text_digest.cache_clear()
        assert _digest(tmp_path, CODE) == provenance._syntax_digest(CODE.encode())
        assert not (tmp_path / "~").exists()
    provenance._text_digest.cache_clear()
