# Chapter 5: rules are added here as its experiments land (see CONTRIBUTING.md §3).
# Until then its target is empty and the report shows "not run".
