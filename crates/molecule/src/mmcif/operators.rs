//! `_pdbx_struct_oper_list` and `_pdbx_struct_assembly_gen`: the operators of a structure's
//! biological assemblies, and the `oper_expression`s that combine them.

use super::{Reader, MAX_OPERATORS};
use crate::assembly::{Assembly, AssemblyPart, Operator};
use crate::error::{quote, Error};
use crate::field::parse_f32;

impl Reader<'_> {
    pub(super) fn operator_row(&mut self, line: u64) -> Result<(), Error> {
        let Some(table) = &self.table else { return Ok(()) };
        let find = |name: &str| {
            table
                .items
                .iter()
                .position(|i| i.eq_ignore_ascii_case(name.as_bytes()))
                .and_then(|at| table.text_row.get(at))
        };
        let id = String::from_utf8_lossy(find("id").map(Vec::as_slice).unwrap_or_default()).into_owned();
        let mut rows = [[0.0_f64; 4]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, value) in row.iter_mut().enumerate() {
                let (name, field) = if j == 3 {
                    (format!("vector[{}]", i + 1), "vector")
                } else {
                    (format!("matrix[{}][{}]", i + 1, j + 1), "matrix")
                };
                let text =
                    find(&name).ok_or_else(|| self.malformed(line, format!("_pdbx_struct_oper_list has no {name}")))?;
                *value = f64::from(parse_f32(text).map_err(|why| Error::Field {
                    file: self.file.to_owned(),
                    line,
                    record: "_pdbx_struct_oper_list",
                    field,
                    value: quote(text),
                    why,
                })?);
            }
        }
        self.operator_order.push(id.clone());
        self.operators.insert(id.clone(), Operator::from_file_rows(id, rows));
        Ok(())
    }

    /// The assemblies `_pdbx_struct_assembly_gen` builds from `_pdbx_struct_oper_list`.
    pub(super) fn assemblies(&self) -> Result<Vec<Assembly>, Error> {
        let mut assemblies: Vec<Assembly> = Vec::new();
        for generator in &self.generators {
            let operators = self.expand(&generator.expression, generator.line)?;
            let part = AssemblyPart { chains: generator.chains.clone(), operators };
            match assemblies.iter_mut().find(|a| a.id == generator.assembly) {
                Some(assembly) => assembly.parts.push(part),
                None => assemblies.push(Assembly { id: generator.assembly.clone(), parts: vec![part] }),
            }
        }
        Ok(assemblies)
    }

    /// The operators of an `oper_expression`: groups `(a,b-c)` multiplied left to right, the
    /// left factor applying last.
    fn expand(&self, expression: &str, line: u64) -> Result<Vec<Operator>, Error> {
        let bad = |why: String| {
            self.malformed(line, format!("_pdbx_struct_assembly_gen oper_expression = {expression:?}: {why}"))
        };
        let mut groups: Vec<Vec<&Operator>> = Vec::new();
        let text = expression.trim();
        let mut rest = text;
        while !rest.is_empty() {
            let (group, after) = if let Some(inner) = rest.strip_prefix('(') {
                let close = inner.find(')').ok_or_else(|| bad("unclosed (".to_owned()))?;
                (inner.get(..close).unwrap_or_default(), inner.get(close + 1..).unwrap_or_default())
            } else if groups.is_empty() && !rest.contains('(') {
                (rest, "")
            } else {
                return Err(bad("expected (".to_owned()));
            };
            let mut operators = Vec::new();
            for item in group.split(',').map(str::trim) {
                let range = item
                    .split_once('-')
                    .and_then(|(a, b)| Some((a.trim().parse::<u64>().ok()?, b.trim().parse::<u64>().ok()?)));
                match range {
                    Some((first, last)) => {
                        if last < first || last - first >= self.operators.len() as u64 {
                            return Err(bad(format!(
                                "range {item} does not match the {} operators listed",
                                self.operators.len()
                            )));
                        }
                        for id in first..=last {
                            operators.push(self.operator(&id.to_string(), &bad)?);
                        }
                    }
                    None => operators.push(self.operator(item, &bad)?),
                }
            }
            groups.push(operators);
            rest = after.trim_start();
        }
        let Some(last) = groups.pop() else { return Err(bad("no operator".to_owned())) };
        let mut product: Vec<Operator> = last.into_iter().cloned().collect();
        while let Some(left) = groups.pop() {
            if left.len().saturating_mul(product.len()) > MAX_OPERATORS {
                return Err(bad(format!("more than {MAX_OPERATORS} operators")));
            }
            product = left.iter().flat_map(|l| product.iter().map(|r| l.after(r))).collect();
        }
        Ok(product)
    }

    fn operator(&self, id: &str, bad: &dyn Fn(String) -> Error) -> Result<&Operator, Error> {
        self.operators.get(id).ok_or_else(|| bad(format!("operator {id:?} is not in _pdbx_struct_oper_list")))
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{read_text, SMALL};

    #[test]
    fn oper_expressions_expand_ranges_lists_and_products() {
        let mut text = SMALL.replace("(1,2)", "(1-2)(2)");
        let m = read_text(&text, true).unwrap();
        let ops = &m.assemblies()[0].parts[0].operators;
        assert_eq!(ops.iter().map(|o| o.id.as_str()).collect::<Vec<_>>(), ["1x2", "2x2"], "product, left applies last");
        // The 2-fold about z with a shift of 5 along z, twice: the turns cancel, the shifts add
        // (file +10 along z, ours -10).
        let twice = ops[1].apply(glam::Vec3::ONE);
        assert!(twice.abs_diff_eq(glam::Vec3::new(1.0, 1.0, -9.0), 1e-5), "a screw axis twice: {twice}");
        text = SMALL.replace("(1,2)", "(1-5)");
        let e = read_text(&text, true).unwrap_err();
        assert!(e.to_string().contains("range 1-5 does not match the 2 operators"), "{e}");
        text = SMALL.replace("(1,2)", "(1,7)");
        let e = read_text(&text, true).unwrap_err();
        assert!(e.to_string().contains(r#"operator "7" is not in _pdbx_struct_oper_list"#), "{e}");
        let m = read_text(&text, false).unwrap();
        assert!(
            m.assemblies().is_empty() && m.warnings().iter().any(|w| w.message.starts_with("assemblies ignored")),
            "only a warning"
        );
    }
}
