"""The sizing engine: checks, motor envelopes, the compiled candidate pass, selection and the result."""
