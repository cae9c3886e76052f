"""``reference``: the semi-analytic contact-locus method (:mod:`lutmpi.contact.locus`) as a
contact method. The rigid two-point contact every method starts from is its result
(:func:`lutmpi.pose.rigid.rigid_result`): no mesh, no k_c (stored as NaN), indentation 0."""

from __future__ import annotations

from lutmpi.contact.methods.base import ContactMethod

METHOD = ContactMethod("reference", "semi-analytic contact locus, rigid two-point contact")
